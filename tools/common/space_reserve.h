#pragma once
// Disk space held back for a study's last words. On a full file system the
// study's final manifest (which turns "running" into "finished" or
// "failed") could not be written, and a resumed study would believe the
// last one still ran. The study writes a reserve file at its start, a
// little larger than its manifest; when a final write fails, it removes the
// reserve and tries again in the space given back.

#include <cstddef>
#include <string>

namespace dynapath::cli {

class SpaceReserve {
 public:
  // Writes `bytes` zero bytes to `path`; a reserve that cannot be written
  // (the disk is already full) is removed and holds nothing.
  SpaceReserve(std::string path, size_t bytes);
  SpaceReserve(const SpaceReserve&) = delete;
  SpaceReserve& operator=(const SpaceReserve&) = delete;
  ~SpaceReserve() { Release(); }

  // Removes the file, giving its space back. True when it held any.
  bool Release();
  size_t bytes() const { return bytes_; }

 private:
  std::string path_;
  size_t bytes_ = 0;
};

}  // namespace dynapath::cli
