#pragma once
// The tiled, parallel pixel loop shared by every renderer: deterministic sub-pixel jitter
// seeded by the pixel index, compositing over the background, progress and cancellation.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/render.hpp>

#include "core/progress_reporter.hpp"
#include "render/shading.hpp"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>

namespace clustersurf::render {

/// The pixel loop's patches (also the parallel loop's grain) and blocks, in pixels a side.
inline constexpr int kPatch = 16, kBlock = 4;

/// What one camera ray sees: a color with coverage `alpha` (0: background only).
struct SampleResult {
  Color rgb = Color::Zero();
  double alpha = 0;
};

/// Checks the options every renderer shares; throws OptionError.
void check_common_options(const RenderOptions& options);

/// The camera of a scene stored relative to `origin` (its box `own` in those coordinates):
/// options.framing, camera.eye and camera.target are in the files' coordinates, so several
/// scenes far from zero, each with its own origin, share one camera.
Camera scene_camera(const RenderOptions& options, const BoundingBox& own, const Eigen::Vector3d& origin, UpAxis up);

/// Traces options.samples rays per pixel of `camera`. `make_tracer(x0, y0, x1, y1)` is called
/// once per tile (pixels [x0, x1) × [y0, y1)) and returns a callable (const Ray&, std::uint64_t seed) → SampleResult
/// owning its scratch memory. The tile is visited by patches of at most kPatch × kPatch pixels
/// (counted from its first pixel), each by blocks of at most kBlock × kBlock; a tracer with
/// enter_patch(x0, y0, x1, y1) is told each patch before its blocks, and one with
/// enter_block(x0, y0, x1, y1) each block before its rays, returning whether a ray of the block
/// may see anything: the pixels of a block it says none of get the background without their
/// rays. The picture does not depend on the thread count.
template <class MakeTracer>
Image trace_image(const Camera& camera, const RenderOptions& options, MakeTracer&& make_tracer, RenderStats* stats,
                  const ProgressCallback& progress_callback) {
  const int w = camera.width, h = camera.height, samples = options.samples;
  Image image(w, h);
  const Color background = to_color({options.background.r, options.background.g, options.background.b});
  const double background_alpha = options.background.a / 255.0;
  detail::ProgressReporter progress(progress_callback, "ray tracing",
                                    static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h));
  std::atomic<std::uint64_t> hits{0};
  const auto start = std::chrono::steady_clock::now();
  const double focal = camera.focal_pixels();
  // The pixel of premultiplied color `sum` with coverage `coverage` over the background.
  const auto over_background = [&](const Color& sum, double coverage) {
    const Color premultiplied = sum + (1 - coverage) * background_alpha * background;
    const double alpha = coverage + (1 - coverage) * background_alpha;
    return alpha > 0 ? to_pixel(premultiplied / alpha, alpha) : Rgba8{0, 0, 0, 0};
  };
  // Pixel (x, y) traced with options.samples rays and composited over the background; returns
  // whether its first ray hit.
  const auto trace_pixel = [&](auto& trace, int x, int y) {
    const std::uint64_t pixel =
        static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
    Color sum = Color::Zero();  // premultiplied
    double coverage = 0;
    bool hit = false;
    for (int k = 0; k < samples; ++k) {
      const std::uint64_t seed = detail::splitmix64(pixel * 1024 + static_cast<std::uint64_t>(k));
      double jx = 0.5, jy = 0.5;
      if (samples > 1)
        jx = unit_interval(detail::splitmix64(seed ^ 0x1234)), jy = unit_interval(detail::splitmix64(seed ^ 0x5678));
      const SampleResult r = trace(camera.ray(x + jx, y + jy, focal), seed);
      sum += r.alpha * r.rgb;
      coverage += r.alpha;
      hit = hit || (k == 0 && r.alpha > 0);
    }
    sum /= samples;
    coverage /= samples;
    image.at(x, y) = over_background(sum, coverage);
    return hit;
  };
  const Rgba8 empty_pixel = over_background(Color::Zero(), 0);
  tbb::parallel_for(tbb::blocked_range2d<int>(0, h, kPatch, 0, w, kPatch), [&](const tbb::blocked_range2d<int>& tile) {
    progress.check();
    const int tx0 = tile.cols().begin(), ty0 = tile.rows().begin(), tx1 = tile.cols().end(), ty1 = tile.rows().end();
    auto trace = make_tracer(tx0, ty0, tx1, ty1);
    std::uint64_t tile_hits = 0;
    // Patch by patch of kPatch × kPatch pixels, block by block within each.
    for (int py = ty0; py < ty1; py += kPatch)
      for (int px = tx0; px < tx1; px += kPatch) {
        const int px1 = std::min(px + kPatch, tx1), py1 = std::min(py + kPatch, ty1);
        if constexpr (requires { trace.enter_patch(px, py, px1, py1); }) trace.enter_patch(px, py, px1, py1);
        for (int by = py; by < py1; by += kBlock)
          for (int bx = px; bx < px1; bx += kBlock) {
            const int bx1 = std::min(bx + kBlock, tx1), by1 = std::min(by + kBlock, ty1);
            if constexpr (requires { trace.enter_block(bx, by, bx1, by1); })
              if (!trace.enter_block(bx, by, bx1, by1)) {
                for (int y = by; y != by1; ++y)
                  for (int x = bx; x != bx1; ++x) image.at(x, y) = empty_pixel;
                continue;
              }
            for (int y = by; y != by1; ++y)
              for (int x = bx; x != bx1; ++x) tile_hits += trace_pixel(trace, x, y) ? 1 : 0;
          }
      }
    hits += tile_hits;
    progress.advance(tile.rows().size() * tile.cols().size());
  });
  progress.finish();
  if (stats != nullptr) {
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->rays = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * static_cast<std::uint64_t>(samples);
    stats->hits = hits.load();
    stats->rays_per_second = stats->seconds > 0 ? static_cast<double>(stats->rays) / stats->seconds : 0;
  }
  return image;
}

}  // namespace clustersurf::render
