#pragma once
// The exception families clustersurf throws. Every public function reports failure by throwing
// one of these (or std::bad_alloc); the CLI catches them once and maps each family to an exit
// code.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace clustersurf {

/// Base of every clustersurf error; what() is a complete, user-readable message.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where in a file an input error was found: a 1-based line (text) or a byte offset (binary).
struct FileLocation {
  std::optional<std::uint64_t> line;
  std::optional<std::uint64_t> byte_offset;
};

/// A file's content is malformed or unsupported (point clouds, meshes, tree files).
/// what() reads "FILE:line N: message" or "FILE: byte N: message" (just the message for data
/// passed in memory, with no file).
class InputError : public Error {
 public:
  InputError(std::filesystem::path file, FileLocation where, const std::string& message);
  const std::filesystem::path& file() const noexcept { return file_; }
  const FileLocation& where() const noexcept { return where_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::filesystem::path file_;
  FileLocation where_;
  std::string message_;
};

/// The operating system refused an I/O operation (missing file, permission, disk full).
class IoError : public Error {
 public:
  using Error::Error;
};

/// A caller passed an invalid option or argument (out of range, inconsistent).
class OptionError : public Error {
 public:
  using Error::Error;
};

/// A progress callback asked to stop; the operation left no partial output.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace clustersurf
