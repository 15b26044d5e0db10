#include "dynapath/convq_model.h"

#include <cmath>

namespace dynapath {

std::array<double, kConvQWeightCount> ConvQWeights(const ConvQModel& model) {
  return {
#define DYNAPATH_CONVQ_READ(name) model.name,
      DYNAPATH_CONVQ_WEIGHTS(DYNAPATH_CONVQ_READ)
#undef DYNAPATH_CONVQ_READ
  };
}

ConvQModel ConvQModelFromWeights(const std::array<double, kConvQWeightCount>& weights) {
  ConvQModel model;
  size_t i = 0;
#define DYNAPATH_CONVQ_WRITE(name) model.name = weights[i++];
  DYNAPATH_CONVQ_WEIGHTS(DYNAPATH_CONVQ_WRITE)
#undef DYNAPATH_CONVQ_WRITE
  return model;
}

const std::array<const char*, kConvQWeightCount>& ConvQWeightNames() {
  static const std::array<const char*, kConvQWeightCount> names = {
#define DYNAPATH_CONVQ_NAME(name) #name,
      DYNAPATH_CONVQ_WEIGHTS(DYNAPATH_CONVQ_NAME)
#undef DYNAPATH_CONVQ_NAME
  };
  return names;
}

Status CheckConvQModel(const ConvQModel& model) {
  const std::array<double, kConvQWeightCount> weights = ConvQWeights(model);
  for (size_t i = 0; i < kConvQWeightCount; ++i) {
    const bool discount = i >= 3;
    const double value = weights[i];
    const bool ok = discount ? (value >= 0.0 && value <= kMaxConvQDiscount)
                             : (std::isfinite(value) && std::fabs(value) <= kMaxConvQReward);
    if (!ok) {
      return Error::Corrupt(std::string("weight ") + ConvQWeightNames()[i] + " is out of bounds (" +
                            (discount ? "0 to 0.999" : "-1e6 to 1e6") + ")");
    }
  }
  return Ok{};
}

ConvQModel SpecConvQModel() { return ConvQModel{100.0, -1.0, -10.0, 0.9, 0.9}; }

}  // namespace dynapath
