#include "kept_ripple_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <stdexcept>

#include "frame_tables.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"
#include "parallel.hpp"

namespace grainlab::validation {

using ripples::hybrid::BedFrame;

namespace {

constexpr const char* kKind = "grainlab-hybrid-suite-ripple-run/1";

// The kept file's frames, with the run restored to the last of them.
std::vector<BedFrame> read_kept(const std::string& path, const std::string& fingerprint,
                                ripples::hybrid::RippleRun& run, const ripples::hybrid::RippleOptions& o) {
  const bool sizes = !o.sizes.empty();
  std::map<std::string, std::vector<std::string>> wanted =
      ripples::hybrid::frame_table_names(sizes, "frames/");
  for (const SampleTable& t : run.save("run/")) wanted[t.name] = t.columns;
  const TableFile file = read_sample_tables(path, wanted);
  require_checkpoint(file, path, kKind, "suite's kept ripple run", fingerprint,
                     "was written for another run: run validate without --resume");
  try {
    run.restore(file.tables, "run/");
    return ripples::hybrid::frames_of_tables(file.tables, run.bed().nx(), run.bed().cell() / o.diameter,
                                             sizes, "frames/");
  } catch (const std::invalid_argument& e) {
    throw InputError({path, 0}, "--resume", e.what());
  }
}

// The frames after those in `frames` (the first, at the start, if there are none) to o.duration; `after`
// is called after each frame the run advances to.
void take_frames(ripples::hybrid::RippleRun& run, const ripples::hybrid::RippleOptions& o,
                 std::vector<BedFrame>& frames, const std::function<void()>& after) {
  if (frames.empty()) frames.push_back(run.frame());
  const std::vector<double> times = ripples::hybrid::frame_times(o.duration, o.frame_every);
  for (std::size_t k = frames.size(); k < times.size(); ++k) {
    run.advance_to(times[k]);
    frames.push_back(run.frame());
    after();
  }
}

}  // namespace

std::vector<BedFrame> run_frames(ripples::hybrid::RippleRun& run, const ripples::hybrid::RippleOptions& o) {
  std::vector<BedFrame> frames;
  take_frames(run, o, frames, [] {});
  return frames;
}

std::vector<BedFrame> kept_ripple_frames(ripples::hybrid::RippleRun& run,
                                         const ripples::hybrid::RippleOptions& o, const SuiteOptions& so,
                                         const std::string& name) {
  const std::string path = so.ensemble_checkpoint(name);
  if (path.empty()) return run_frames(run, o);
  const std::string fingerprint =
      fmt::format("{}: {} d x {} d, u* {:.17g}, seed {}, {:.17g} t*, frames every {:.17g}", name, o.length,
                  o.width, o.u_star, o.seed, o.duration, o.frame_every);
  std::vector<BedFrame> frames;
  if (std::filesystem::exists(path)) {
    frames = read_kept(path, fingerprint, run, o);
    if (so.log) so.log(fmt::format("continuing the ripple run from t* = {:.0f}", frames.back().t_star));
  }
  const std::size_t total = ripples::hybrid::frame_times(o.duration, o.frame_every).size();
  if (frames.size() > total)
    throw InputError({path, 0}, "--resume",
                     "holds more frames than the run takes: run validate without --resume");
  if (so.progress) so.progress(std::max<std::size_t>(frames.size(), 1), total);
  // Written after every frame (one of the full run takes 15-20 s of one core): keeping them left the quick
  // suite's time unchanged within the machine's noise (docs/validation.md).
  take_frames(run, o, frames, [&] {
    std::vector<SampleTable> tables = run.save("run/");  // collective on a distributed run
    for (SampleTable& t : ripples::hybrid::frame_tables(frames, run.bed().nx(), !o.sizes.empty(), "frames/"))
      tables.push_back(std::move(t));
    if (parallel::rank() == 0)
      write_sample_tables(
          path, tables, {{"kind", kKind}, {"grainlab_version", GRAINLAB_VERSION}, {"options", fingerprint}});
    if (so.progress) so.progress(frames.size(), total);
  });
  return frames;
}

}  // namespace grainlab::validation
