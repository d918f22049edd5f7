#pragma once
// A grainlab-splash/1 file's simulated cells as the hybrid ripple model's recorded splash: the bridge
// between saltation/ (the file) and ripples/ (the model), so that neither library depends on the other.
#include <string>

#include "recorded_splash.hpp"
#include "splash_file.hpp"
#include "transport.hpp"

namespace grainlab::validation {

// Each cell's impacts with their rebound (x along the incident direction, y normal to the bed, the
// lateral column of a 3-D file across) and their ejecta (launch velocity and where they sat). Throws
// InputError naming `path` if a cell holds no recorded impacts (a measured file with moments only).
ripples::hybrid::RecordedSplash recorded_splash(const saltation::SplashFile& f, const std::string& path);

// Reads the file at `path` and converts it (InputError naming the file for anything wrong).
ripples::hybrid::RecordedSplash read_recorded_splash(const std::string& path);

// A splash that is not one of the Lammel sets names a grainlab-splash/1 file of recorded impacts: read it
// into o.recorded (the hybrid commands, and the tests that check configs as the commands run them).
void attach_recorded_splash(ripples::hybrid::TransportOptions& o);

}  // namespace grainlab::validation
