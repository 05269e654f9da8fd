#include <clustersurf/core/errors.hpp>

#include <fmt/format.h>

namespace clustersurf {

namespace {
std::string format_location(const std::filesystem::path& file, const FileLocation& where, const std::string& message) {
  if (file.empty()) return message;
  if (where.line) return fmt::format("{}:{}: {}", file.string(), *where.line, message);
  if (where.byte_offset) return fmt::format("{}: byte {}: {}", file.string(), *where.byte_offset, message);
  return fmt::format("{}: {}", file.string(), message);
}
}  // namespace

InputError::InputError(std::filesystem::path file, FileLocation where, const std::string& message)
    : Error(format_location(file, where, message)), file_(std::move(file)), where_(where), message_(message) {}

}  // namespace clustersurf
