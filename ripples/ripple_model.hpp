#pragma once
// One interface for the surface-evolving ripple models (Haff's bin model, the lattice-bed model), created
// by name from a table as the validation suites are: `grainlab ripples run --config FILE` picks the model
// from the config's table ([bins] or [lattice]) and drives it through this interface.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ripple_config.hpp"

namespace grainlab::ripples {

class RippleModel {
 public:
  virtual ~RippleModel() = default;
  // Advances by `amount` of the model's time unit (see time_unit).
  virtual void advance(double amount) = 0;
  // The surface in grain diameters, one value per `dx()` grain diameters, periodic, wind towards +x.
  virtual std::vector<double> surface() const = 0;
  virtual double dx() const = 0;
  virtual double time() const = 0;
  virtual std::string time_unit() const = 0;
  // Named numbers (grain diameters and degrees) for the history table.
  virtual std::map<std::string, double> diagnostics() const = 0;
};

// A model built from its config: the model, how long the config asks it to run, and how many frames.
struct RippleModelRun {
  std::unique_ptr<RippleModel> model;
  double duration = 0;
  int frames = 100;
  std::string name, text;
};

// Reads a splash file's hops for the lattice model's splash mode, as the run's splash keys ask (the file,
// the cells, and in wind mode the Ch. IV wind). The caller supplies it: ripples/ reads no HDF5.
using SplashHopLoader = std::function<SplashHops(const LatticeRun&)>;

struct RippleModelEntry {
  std::string name, description;
  std::function<RippleModelRun(const std::string& text, const std::string& path, const SplashHopLoader&)>
      create;
};
const std::vector<RippleModelEntry>& ripple_models();
// The model named by the config's table. Throws InputError (no model table, bad keys, a splash file
// asked for without a loader).
RippleModelRun create_ripple_model(const std::string& text, const std::string& path,
                                   const SplashHopLoader& hops = nullptr);

}  // namespace grainlab::ripples
