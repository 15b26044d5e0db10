#pragma once
// Whole-file text I/O. Writes go to a temporary file in the same directory
// which is then renamed, so a reader never sees a half-written file.

#include <string>

#include "core/result.h"

namespace dynapath {

Result<std::string> ReadTextFile(const std::string& path);
Status WriteTextFileAtomically(const std::string& path, const std::string& contents);

}  // namespace dynapath
