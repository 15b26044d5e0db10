#pragma once
// Whole-file text I/O. Writes go to a temporary file in the same directory
// which is then renamed, so a reader never sees a half-written file.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dynapath/result.h"

namespace dynapath {

Result<std::string> ReadTextFile(const std::string& path);
// The one atomic writer of the project: `contents` go to a temporary file
// beside `path` (same file system, so the rename is atomic), renamed over it.
Status WriteFileAtomically(const std::string& path, std::string_view contents);
inline Status WriteFileAtomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  return WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}
// WriteFileAtomically that also syncs the file before the rename and the
// folder after it: after a crash or power loss the path holds the old
// contents or the new, whole (checkpoints).
Status WriteFileDurably(const std::string& path, std::string_view contents);
inline Status WriteTextFileAtomically(const std::string& path, const std::string& contents) {
  return WriteFileAtomically(path, std::string_view(contents));
}

}  // namespace dynapath
