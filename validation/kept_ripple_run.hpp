#pragma once
// The hybrid suite's ripple runs frame by frame, and kept as they go: the full suite's ripple run takes
// 15-20 min of one core, so `validate --resume` continues it from its last frame instead of its start.
#include <string>
#include <vector>

#include "ripple_run.hpp"
#include "suites.hpp"

namespace grainlab::validation {

// Every frame of a run from its start to o.duration.
std::vector<ripples::hybrid::BedFrame> run_frames(ripples::hybrid::RippleRun& run,
                                                  const ripples::hybrid::RippleOptions& o);

// run_frames kept in the suite's ensembles folder (SuiteOptions::ensembles_dir) under `name`: the run's
// state and its frames after every frame, so that a stopped run continues from its last frame and ends
// with the frames and bed of a run never stopped (on any rank count). so.progress hears of each frame.
// Without a folder, run_frames. Throws InputError (naming the file, key "--resume") for a kept file that
// is damaged or another run's.
std::vector<ripples::hybrid::BedFrame> kept_ripple_frames(ripples::hybrid::RippleRun& run,
                                                          const ripples::hybrid::RippleOptions& o,
                                                          const SuiteOptions& so, const std::string& name);

}  // namespace grainlab::validation
