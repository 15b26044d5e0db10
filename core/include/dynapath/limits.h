#pragma once
// Limits shared by every way a grid enters DynaPath: the command line, study
// configs, maze files and the network protocol. One constant, so raising it
// changes all of them together (and the protocol's message size caps, which
// are derived from it: protocol/limits.h).

namespace dynapath {

// Largest number of rows or columns of a grid.
inline constexpr int kMaxGridSide = 4096;

}  // namespace dynapath
