#include "ripple_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "input_error.hpp"
#include "ripple_config.hpp"
#include "surface_analysis.hpp"
#include "toml_reader.hpp"

namespace grainlab::ripples {

namespace {

std::map<std::string, double> shape_diagnostics(const std::vector<double>& h, double dx) {
  double mean = 0, var = 0;
  for (double v : h) mean += v;
  mean /= static_cast<double>(h.size());
  for (double v : h) var += (v - mean) * (v - mean);
  const double rms = std::sqrt(var / static_cast<double>(h.size()));
  const SurfaceShape s = surface_shape(h, dx, std::max(0.5 * rms, 1e-9));
  // Two wavelengths: the crests' mean spacing counts every bump half the rms proud, grain-scale roughness
  // too; the autocorrelation's (the measure the lattice runs are compared with the thesis by) the pattern's.
  return {{"rms", rms},
          {"wavelength", s.wavelength},
          {"autocorrelation_wavelength", autocorrelation_wavelength(h) * dx},
          {"height", s.height},
          {"ripple_index", s.ripple_index},
          {"stoss_deg", s.stoss_deg},
          {"lee_deg", s.lee_deg}};
}

class BinRipples : public RippleModel {
 public:
  explicit BinRipples(const BinModelParams& p) : p_(p), m_(p) {}
  void advance(double shots) override { m_.fire(std::lround(shots)); }
  std::vector<double> surface() const override { return m_.heights(); }
  double dx() const override { return p_.bin_width; }
  double time() const override { return static_cast<double>(m_.shots_fired()); }
  std::string time_unit() const override { return "shots"; }
  std::map<std::string, double> diagnostics() const override { return shape_diagnostics(surface(), dx()); }

 private:
  BinModelParams p_;
  BinModel m_;
};

class LatticeRipples : public RippleModel {
 public:
  explicit LatticeRipples(const LatticeParams& p) : p_(p), m_(p) {}
  void advance(double ejections_per_grain) override {
    m_.fire(std::lround(ejections_per_grain * p_.columns / 2));
  }
  std::vector<double> surface() const override { return lattice_profile(m_.heights()); }
  double dx() const override { return std::sqrt(3.0); }
  double time() const override { return m_.ejections_per_surface_grain(); }
  std::string time_unit() const override { return "ejections per surface grain"; }
  std::map<std::string, double> diagnostics() const override { return shape_diagnostics(surface(), dx()); }

 private:
  LatticeParams p_;
  LatticeModel m_;
};

}  // namespace

const std::vector<RippleModelEntry>& ripple_models() {
  static const std::vector<RippleModelEntry> all = {
      {"bins", "Haff's bin model: shots at a fixed angle, shadowing, relaxation at the angle of repose",
       [](const std::string& text, const std::string& path, const SplashHopLoader&) {
         BinModelRun r = parse_bin_model_config(text, path);
         return RippleModelRun{std::make_unique<BinRipples>(r.params), double(r.shots), r.frames, "bins",
                               text};
       }},
      {"lattice", "the lattice-bed model (Fig. 5.21): target and brink ejection on a 30 deg lattice",
       [](const std::string& text, const std::string& path, const SplashHopLoader& hops) {
         LatticeRun r = parse_lattice_config(text, path);
         if (!r.splash.empty()) {
           if (!hops) throw InputError({path, 0}, "lattice.splash", "splash files cannot be read here");
           apply_splash_hops(r, hops(r));
         }
         return RippleModelRun{std::make_unique<LatticeRipples>(r.params), r.ejections_per_grain, r.frames,
                               "lattice", text};
       }},
  };
  return all;
}

RippleModelRun create_ripple_model(const std::string& text, const std::string& path,
                                   const SplashHopLoader& hops) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError({path, static_cast<int>(e.source().begin.line)}, "", std::string(e.description()));
  }
  std::string names;
  for (const RippleModelEntry& m : ripple_models()) {
    names += (names.empty() ? "[" : ", [") + m.name + "]";
    if (root.contains(m.name)) return m.create(text, path, hops);
  }
  // The configs of the models with commands of their own (scenes/ripples/ holds one of each).
  for (const char* own : {"triangles", "worms", "hybrid"})
    if (root.contains(own))
      throw InputError(
          {path, 0}, "",
          fmt::format("is a [{0}] config: run it with `grainlab ripples {0} --config {1}`; `ripples "
                      "run` takes one table of {2}",
                      own, path, names));
  throw InputError({path, 0}, "", "names no ripple model; give one table of " + names);
}

}  // namespace grainlab::ripples
