// The weights of docs/examples/models/convq.model (`dynapath train-model
// --seed 1`), written by `dynapath train-model --print-weights`.
#include "dynapath/convq_model.h"

namespace dynapath {

const ConvQModel& ShippedConvQModel() {
  static const ConvQModel model{100.0, -1.0, -10.0, 0.9, 0.9};
  return model;
}

}  // namespace dynapath
