#include "io/atomic_file.hpp"

#include <clustersurf/core/errors.hpp>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace clustersurf::io {

namespace {
[[noreturn]] void fail(const std::filesystem::path& file, const char* what, int err) {
  throw IoError(file.string() + ": " + what + ": " + std::strerror(err));
}
}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  if (target_.empty()) throw IoError("empty output file name");
  std::filesystem::path dir = target_.parent_path();
  if (dir.empty()) dir = ".";
  std::string pattern = (dir / ("." + target_.filename().string() + ".tmpXXXXXX")).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) fail(target_, "cannot create a temporary file in its directory", errno);
  temp_ = pattern;
  file_ = ::fdopen(fd, "wb");
  if (file_ == nullptr) {
    const int err = errno;
    ::close(fd);
    std::filesystem::remove(temp_);
    fail(target_, "cannot open a temporary file", err);
  }
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::write(const void* data, std::size_t size) {
  if (size != 0 && std::fwrite(data, 1, size, file_) != size) fail(target_, "write failed", errno);
}

void AtomicFile::commit() {
  if (std::fflush(file_) != 0) fail(target_, "write failed", errno);
  if (::fsync(::fileno(file_)) != 0 && errno != EINVAL) fail(target_, "sync failed", errno);
  // Temporary files are created 0600; give the result the usual permissions (umask applies).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(::fileno(file_), 0666 & ~mask);
  if (std::fclose(file_) != 0) {
    file_ = nullptr;
    std::filesystem::remove(temp_);
    fail(target_, "close failed", errno);
  }
  file_ = nullptr;
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) {
    std::filesystem::remove(temp_);
    throw IoError(target_.string() + ": cannot rename the temporary file onto it: " + ec.message());
  }
}

}  // namespace clustersurf::io
