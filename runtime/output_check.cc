#include "runtime/output_check.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace dynapath::runtime {
namespace {

namespace fs = std::filesystem;

Error Bad(const std::string& option, const std::string& detail) {
  return Error("option --" + option + ": " + detail, Error::Code::kInvalidArgument, option);
}

// 0, or the errno of stat().
int Stat(const std::string& path, struct stat& info) {
  return stat(path.c_str(), &info) == 0 ? 0 : errno;
}

// Whether files can be made in `dir`, as the atomic writers do (a
// temporary file, then a rename). access() answers yes to root everywhere
// and knows nothing of file systems that take no new files (/proc, /sys):
// one is made and removed.
Status Writable(const std::string& dir, const std::string& what, const std::string& option) {
  std::string probe = (fs::path(dir) / ".dynapath-probe.XXXXXX").string();
  const int fd = mkstemp(probe.data());
  if (fd < 0) {
    const int error = errno;
    return Bad(option, what + " is not writable: " + std::strerror(error));
  }
  close(fd);
  unlink(probe.c_str());
  return Ok{};
}

}  // namespace

Status PrepareOutputDirectory(const std::string& dir, const std::string& option) {
  if (dir.empty()) return Bad(option, "must not be empty");
  struct stat info {};
  int error = Stat(dir, info);
  if (error == 0 && !S_ISDIR(info.st_mode)) {
    return Bad(option, dir + " is a file, not a directory");
  }
  if (error == ENOENT || error == ENOTDIR) {  // missing, or under a file: say why it cannot be made
    std::error_code created;
    fs::create_directories(dir, created);
    if (created) return Bad(option, dir + ": cannot create the directory: " + created.message());
    error = Stat(dir, info);
  }
  if (error != 0) return Bad(option, dir + ": " + std::strerror(error));
  return Writable(dir, dir, option);
}

Status CheckOutputFiles(const std::string& dir, const std::vector<std::string>& names,
                        const std::string& option) {
  for (const std::string& name : names) {
    const std::string path = (fs::path(dir) / name).string();
    struct stat info {};
    if (Stat(path, info) == 0 && S_ISDIR(info.st_mode)) {
      return Bad(option, path + " is a directory, where the file " + name + " is to be written");
    }
  }
  return Ok{};
}

Status CheckOutputFile(const std::string& path, const std::string& option) {
  if (path.empty()) return Bad(option, "must not be empty");
  struct stat info {};
  const int error = Stat(path, info);
  if (error == 0 && S_ISDIR(info.st_mode)) {
    return Bad(option, path + " is a directory, not a file");
  }
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  struct stat folder {};
  if (const int missing = Stat(parent.string(), folder); missing != 0) {
    return Bad(option, path + ": its folder " + parent.string() + " " +
                           (missing == ENOENT ? "does not exist" : std::strerror(missing)));
  }
  if (!S_ISDIR(folder.st_mode)) {
    return Bad(option, path + ": " + parent.string() + " is not a directory");
  }
  if (error == 0 && access(path.c_str(), W_OK) != 0) {
    const int denied = errno;
    return Bad(option, path + " is not writable: " + std::strerror(denied));
  }
  return Writable(parent.string(), path + ": its folder " + parent.string(), option);
}

}  // namespace dynapath::runtime
