// `grainlab ripples analyze FILE`: the Ch. V analysis of any surface. FILE is a CSV of x, h (a header line
// allowed; x uniform and increasing, taken as periodic) or a ripple run file (`ripples bins|lattice --out`,
// `ripples run --out`, or `ripples hybrid --out` averaged across the wind; its last frame or --frame N).
// Prints wavelength three ways, height, ripple index and slopes.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "bed_statistics.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"
#include "lattice_model.hpp"
#include "option_scope.hpp"
#include "ripple_config.hpp"
#include "ripples_commands.hpp"
#include "surface_analysis.hpp"

namespace grainlab::cli {

using namespace grainlab::ripples;

namespace {

struct Profile {
  std::vector<double> h;
  double dx = 1;
  std::string units, source;
  std::optional<hybrid::BedStatistics> bed;  // a 3-D bed's own measures (Huo et al.'s slices)
};

Profile read_csv_profile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0}, "", "cannot be read");
  Profile p;
  std::vector<double> x;
  std::string line;
  int n = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    double a = 0, b = 0;
    if (!(ss >> a >> b)) {
      if (!header_seen && x.empty()) {  // one header line
        header_seen = true;
        continue;
      }
      throw InputError({path, n}, "", "expected two numbers, x and h, separated by a comma or spaces");
    }
    if (!std::isfinite(a) || !std::isfinite(b)) throw InputError({path, n}, "", "x and h must be finite");
    x.push_back(a), p.h.push_back(b);
  }
  if (x.size() < 8) throw InputError({path, 0}, "", "needs at least 8 points");
  p.dx = (x.back() - x.front()) / static_cast<double>(x.size() - 1);
  if (!(p.dx > 0)) throw InputError({path, 0}, "", "x must increase");
  for (std::size_t i = 1; i < x.size(); ++i)
    if (std::abs(x[i] - x[i - 1] - p.dx) > 1e-6 * std::max(1.0, std::abs(p.dx)) + 1e-9 * std::abs(x[i]))
      throw InputError({path, static_cast<int>(i + 1)}, "", "x must be evenly spaced (resample the profile)");
  p.units = "the file's units";
  p.source = "CSV";
  return p;
}

// A run file's point spacing, its "dx" attribute (InputError unless a positive number).
double spacing_of(const TableFile& f, const std::string& path) {
  double dx = 0;
  if (const auto it = f.metadata.find("dx"); it != f.metadata.end()) try {
      dx = std::stod(it->second);
    } catch (const std::exception&) {
      dx = 0;
    }
  if (!(dx > 0) || !std::isfinite(dx)) throw InputError({path, 0}, "dx", "must be a positive number");
  return dx;
}

// The frame asked for (the last if --frame is not given) of `count`.
std::size_t chosen_frame(int frame, std::size_t count) {
  const long k = frame < 0 ? static_cast<long>(count) - 1 : frame;
  if (k < 0 || k >= static_cast<long>(count))
    throw InputError({"--frame", 0}, std::to_string(frame),
                     fmt::format("the file has frames 0..{}", count - 1));
  return static_cast<std::size_t>(k);
}

// A 3-D bed's height field (`ripples hybrid --out`): the profile averaged across the wind, as the paper
// averages its slices, key points dx apart.
Profile read_grid_profile(const std::string& path, int frame, std::size_t count) {
  if (count == 0) throw InputError({path, 0}, "frames", "has no frames");
  const std::size_t k = chosen_frame(frame, count);
  const GridFrame g = read_grid_frame(path, k);
  const TableFile meta = read_sample_tables(path, {});
  Profile p;
  p.h.assign(g.nx, 0.0);
  for (std::size_t row = 0; row < g.ny; ++row)
    for (std::size_t i = 0; i < g.nx; ++i) p.h[i] += g.values[row * g.nx + i] / static_cast<double>(g.ny);
  p.dx = spacing_of(meta, path);
  p.units = "grain diameters";
  p.bed = hybrid::bed_statistics(g.values, g.nx, g.ny, p.dx);
  const auto model = meta.metadata.find("model");
  p.source = fmt::format("{}, frame {} (t = {:.6g}), averaged across its {} rows",
                         model == meta.metadata.end() ? "height field" : model->second, k, g.time, g.ny);
  return p;
}

Profile read_run_profile(const std::string& path, int frame) {
  const std::map<std::string, H5Object> objects = root_objects(path);
  if (!objects.count("h") && objects.count("frames") && !objects.at("frames").dataset)
    return read_grid_profile(path, frame, objects.at("frames").members);
  if (!objects.count("h"))
    throw InputError(
        {path, 0}, "file",
        "holds no surface: ripples analyze reads the runs of ripples bins, lattice, run and hybrid "
        "(--out) and CSV files of x, h");
  const TableFile f = read_sample_tables(path, {{"h", {}}});
  const SampleTable& h = f.tables.at("h");
  if (h.rows.empty()) throw InputError({path, 0}, "h", "has no frames");
  const std::vector<double>& row = h.rows[chosen_frame(frame, h.rows.size())];
  Profile p;
  const auto model = f.metadata.count("model") ? f.metadata.at("model") : std::string();
  if (f.metadata.count("dx")) {
    // `ripples run`'s layout: the surface as the model gives it, in grain diameters, dx apart (a lattice's
    // already one point per lattice spacing).
    p.h = row;
    p.dx = spacing_of(f, path);
    p.units = "grain diameters";
  } else if (model.find("lattice") != std::string::npos) {
    // One point per lattice spacing (the mean of its two columns), in grain diameters.
    p.h = lattice_profile(row);
    p.dx = std::sqrt(3.0);
    p.units = "grain diameters";
  } else {
    // Haff's bin model: heights in grain diameters, bins bin_width diameters wide (from the stored config).
    p.h = row;
    const std::string config = f.metadata.count("config") ? f.metadata.at("config") : std::string();
    p.dx = config.find("[bins]") != std::string::npos ? parse_bin_model_config(config, path).params.bin_width
                                                      : BinModelParams{}.bin_width;
    p.units = "grain diameters";
  }
  p.source = model.empty() ? "run file" : model;
  return p;
}

}  // namespace

int analyze_command(const RipplesCommands& a) {
  const bool csv = a.analyze_file.size() > 4 && a.analyze_file.substr(a.analyze_file.size() - 4) == ".csv";
  if (csv) refuse_if_given(a.analyze->get_option("--frame"), "is for run files (a CSV holds one profile)");
  const Profile p =
      csv ? read_csv_profile(a.analyze_file) : read_run_profile(a.analyze_file, a.analyze_frame);
  // (The profile is periodic: a half-width past half of it would take the same points again.)
  if (2 * static_cast<std::size_t>(a.analyze_smooth) > p.h.size())
    throw InputError({"--smooth", 0}, std::to_string(a.analyze_smooth),
                     fmt::format("must be at most half the profile's {} points", p.h.size()));
  const std::vector<double> smooth =
      a.analyze_smooth > 0 ? tombrello_smooth(p.h, a.analyze_smooth, a.analyze_sigma) : p.h;
  // Crests and troughs must stand out by --relief, by default half the surface's rms height.
  double relief = a.analyze_relief;
  if (relief <= 0) relief = 0.5 * rms_height(smooth);
  const SurfaceShape shape = surface_shape(smooth, p.dx, relief);
  const std::vector<double> f = length_scale_distribution(
      smooth, std::max<int>(1, static_cast<int>(smooth.size() / 4)), a.analyze_sigma);
  const int peak = length_scale_peak(f);
  const std::vector<double> spectrum = power_spectrum(smooth);
  const std::size_t top =
      static_cast<std::size_t>(std::max_element(spectrum.begin(), spectrum.end()) - spectrum.begin());
  const double spectral =
      spectrum.empty() ? 0 : static_cast<double>(smooth.size()) / static_cast<double>(top + 1) * p.dx;
  const double auto_wl = autocorrelation_wavelength(smooth) * p.dx;
  nlohmann::json j{{"source", p.source},
                   {"units", p.units},
                   {"points", smooth.size()},
                   {"dx", p.dx},
                   {"wavelength_crests", shape.wavelength},
                   {"wavelength_autocorrelation", auto_wl},
                   {"wavelength_spectrum", spectral},
                   {"f_lambda_peak", peak * p.dx},
                   {"height", shape.height},
                   {"ripple_index", shape.ripple_index},
                   {"stoss_deg", shape.stoss_deg},
                   {"lee_deg", shape.lee_deg},
                   {"crests", shape.crests},
                   {"rms", shape.rms}};
  if (p.bed)
    j["slices"] = {{"amplitude", p.bed->amplitude},
                   {"wavelength", p.bed->wavelength},
                   {"ripple_index", p.bed->ripple_index},
                   {"crest_spacing", p.bed->crest_spacing},
                   {"crest_height", p.bed->crest_height},
                   {"stoss_deg", p.bed->stoss_deg},
                   {"lee_deg", p.bed->lee_deg}};
  if (a.json) {
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("{}: {} points, dx {} ({})\n", a.analyze_file, smooth.size(), p.dx, p.units);
  fmt::print(
      "  wavelength: {:.3g} (crest spacing), {:.3g} (autocorrelation), {:.3g} (power spectrum), {:.3g} "
      "(f(lambda) peak, eq. 5.2)\n",
      shape.wavelength, auto_wl, spectral, peak * p.dx);
  fmt::print(
      "  height {:.3g}, ripple index {:.3g}, stoss {:.1f} deg, lee {:.1f} deg, {} crests, rms {:.3g}\n",
      shape.height, shape.ripple_index, shape.stoss_deg, shape.lee_deg, shape.crests, shape.rms);
  if (p.bed)
    fmt::print(
        "  slice by slice (Huo et al. 2021, as `ripples hybrid` reports them): amplitude {:.3g}, wavelength "
        "{:.3g} (the autocorrelation's first peak), ripple index {:.3g}; crests {:.3g} apart, {:.3g} high; "
        "stoss {:.1f} deg, lee {:.1f} deg\n",
        p.bed->amplitude, p.bed->wavelength, p.bed->ripple_index, p.bed->crest_spacing, p.bed->crest_height,
        p.bed->stoss_deg, p.bed->lee_deg);
  return 0;
}

}  // namespace grainlab::cli
