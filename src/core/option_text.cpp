// The option schemas' text: numbers, words and vectors written and read back, each failure an
// OptionError naming the option.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/option_spec.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>

namespace clustersurf {

namespace {

/// `text` as a whole finite double, or nothing.
std::optional<double> whole_real(std::string_view text) {
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

}  // namespace

std::string number_text(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(value);
}

std::string vector_text(double x, double y, double z) {
  return number_text(x) + "," + number_text(y) + "," + number_text(z);
}

std::string quoted(std::string_view text) { return "\"" + std::string(text) + "\""; }

std::string word_list(const std::vector<std::string>& words) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i)
    out += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
  return out;
}

std::uint64_t parse_whole(std::string_view name, std::string_view text, std::uint64_t low, std::uint64_t high,
                          std::string_view word) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < low || value > high)
    throw OptionError(std::string(name) + " must be " + (word.empty() ? "" : quoted(word) + " or ") +
                      // A bound of 2^32 - 1 or more only says what the type holds: left unsaid.
                      (high >= 0xFFFFFFFFull
                           ? "a whole number >= " + std::to_string(low)
                           : "a whole number from " + std::to_string(low) + " to " + std::to_string(high)) +
                      ", not " + quoted(text));
  return value;
}

double parse_real_in(std::string_view name, std::string_view text, double low, double high) {
  const std::optional<double> value = whole_real(text);
  if (!value || *value < low || *value > high)
    throw OptionError(std::string(name) + " must be a number from " + number_text(low) + " to " + number_text(high) +
                      ", not " + quoted(text));
  return *value;
}

double parse_real(std::string_view name, std::string_view text, RealBound bound, std::string_view word) {
  const std::optional<double> value = whole_real(text);
  const bool in_range = value && (bound == RealBound::Positive      ? *value > 0
                                  : bound == RealBound::NonNegative ? *value >= 0
                                                                    : true);
  if (!in_range)
    throw OptionError(std::string(name) + " must be " + (word.empty() ? "" : quoted(word) + " or ") + "a " +
                      (bound == RealBound::Positive      ? "positive number"
                       : bound == RealBound::NonNegative ? "number >= 0"
                                                         : "finite number") +
                      ", not " + quoted(text));
  return *value;
}

bool parse_flag(std::string_view name, std::string_view text) {
  if (text == "true") return true;
  if (text == "false") return false;
  throw OptionError(std::string(name) + " must be true or false, not " + quoted(text));
}

std::array<double, 3> parse_vector(std::string_view name, std::string_view text) {
  std::array<double, 3> out{};
  std::size_t start = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t comma = k < 2 ? text.find(',', start) : text.size();
    const std::optional<double> value =
        comma == std::string_view::npos ? std::nullopt : whole_real(text.substr(start, comma - start));
    if (!value || (k == 2 && text.find(',', start) != std::string_view::npos))
      throw OptionError(std::string(name) + " must be three numbers x,y,z, not " + quoted(text));
    out[k] = *value;
    start = comma + 1;
  }
  return out;
}

}  // namespace clustersurf
