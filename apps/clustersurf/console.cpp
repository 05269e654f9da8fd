#include "console.hpp"
#include "interrupt.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace clustersurf::cli {

Console::Console(const GlobalOptions& options) : options_(options) {
  bar_ = !options.quiet && !options.json && ::isatty(STDERR_FILENO) != 0;
  // Warnings and errors go to stderr, keeping stdout for results (and --json).
  spdlog::set_default_logger(spdlog::stderr_color_mt("clustersurf"));
  spdlog::set_pattern("%^%l%$: %v");
  spdlog::set_level(options.quiet ? spdlog::level::err : spdlog::level::info);
}

Console::~Console() { end_progress(); }

void Console::print(const std::string& line) const {
  if (options_.quiet || options_.json) return;
  std::fputs(line.c_str(), stdout);
  std::fputc('\n', stdout);
}

void Console::warn(const std::string& message) const { spdlog::warn("{}", message); }

ProgressCallback Console::progress() {
  if (!bar_) return [](std::string_view, double) { return !interrupt_requested(); };
  return [this](std::string_view stage, double fraction) {
    if (interrupt_requested()) return false;
    const std::lock_guard lock(mutex_);
    const int permille = static_cast<int>(fraction * 1000.0);
    const auto now = std::chrono::steady_clock::now();
    if (stage == stage_ && (permille == last_permille_ || now - last_draw_ < std::chrono::milliseconds(100)) &&
        fraction < 1.0)
      return true;
    stage_ = stage;
    last_permille_ = permille;
    last_draw_ = now;
    constexpr int width = 30;
    const int filled = std::clamp(static_cast<int>(fraction * width), 0, width);
    fmt::print(stderr, "\r{:<22} [{}{}] {:5.1f}%\x1b[K", stage_, std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(width - filled), '.'), 100.0 * fraction);
    std::fflush(stderr);
    drawn_ = true;
    return true;
  };
}

void Console::end_progress() {
  const std::lock_guard lock(mutex_);
  if (drawn_) {
    std::fputs("\r\x1b[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
  }
}

}  // namespace clustersurf::cli
