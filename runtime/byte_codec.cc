#include "runtime/byte_codec.h"

#include <sodium.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <memory>

namespace dynapath::runtime {

void AppendChecksum(ByteWriter& out) {
  unsigned char checksum[kChecksumBytes];
  crypto_generichash(checksum, sizeof(checksum), out.bytes().data(), out.bytes().size(), nullptr,
                     0);
  out.PutBytes(checksum, sizeof(checksum));
}

bool ChecksumMatches(std::string_view bytes) {
  if (bytes.size() < kChecksumBytes) return false;
  unsigned char checksum[kChecksumBytes];
  const size_t covered = bytes.size() - kChecksumBytes;
  crypto_generichash(checksum, sizeof(checksum),
                     reinterpret_cast<const unsigned char*>(bytes.data()), covered, nullptr, 0);
  return std::memcmp(checksum, bytes.data() + covered, kChecksumBytes) == 0;
}

uint64_t Fingerprint64(std::string_view bytes) {
  unsigned char hash[crypto_generichash_BYTES_MIN];
  crypto_generichash(hash, sizeof(hash), reinterpret_cast<const unsigned char*>(bytes.data()),
                     bytes.size(), nullptr, 0);
  uint64_t value = 0;
  std::memcpy(&value, hash, sizeof(value));
  return value;
}

Result<std::string> ReadBoundedFile(const std::string& path, uint64_t max_bytes,
                                    const std::string& what) {
  const std::string name = what + " " + path + ": ";
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return Error::File(errno, name + std::strerror(errno));
  struct stat info {};
  if (fstat(fileno(file.get()), &info) != 0) return Error::File(errno, name + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) return Error::Corrupt(name + "not a regular file");
  if (static_cast<uint64_t>(info.st_size) > max_bytes) {
    return Error::Corrupt(name + std::to_string(info.st_size) + " bytes, more than any " + what +
                          " (" + std::to_string(max_bytes) + ")");
  }
  std::string bytes(static_cast<size_t>(info.st_size), '\0');
  if (!bytes.empty() && std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
    return Error::File(errno, name + std::strerror(errno));
  }
  return bytes;
}

}  // namespace dynapath::runtime
