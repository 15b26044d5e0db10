#pragma once
// What protocol::Validate finds wrong with a message, for the tests: "" when
// the message is valid, else the refusal's message; every refusal must carry
// the code kCorrupt (a test fails otherwise).

#include <gtest/gtest.h>

#include <string>

#include "protocol/validate.h"

namespace dynapath::protocol {

template <typename T>
std::string ValidationProblem(const T& message) {
  const Status valid = Validate(message);
  if (valid) return "";
  EXPECT_TRUE(valid.error().IsCorrupt())
      << "refused with code " << CodeName(valid.error().code) << ": " << valid.error().message;
  return valid.error().message;
}

}  // namespace dynapath::protocol
