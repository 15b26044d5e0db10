// The weights of docs/examples/models/convq.model (`dynapath train-model
// --seed 1 --out docs/examples/models/convq.model`), as its last log line
// prints them (exact, hexadecimal).
#include "dynapath/convq_model.h"

namespace dynapath {

const ConvQModel& ShippedConvQModel() {
  static const ConvQModel model{0x1.8ffffdbbe8b2bp+6, -0x1.ffffff8cb897ap-1, -0x1.3fffffa9e4bb3p+3,
                                0x1.cccccccb36a39p-1, 0x1.ccccccb9967a5p-1};
  return model;
}

}  // namespace dynapath
