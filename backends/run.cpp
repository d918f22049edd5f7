#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "engine.hpp"

namespace grainlab {

namespace {
std::vector<double> energy_row(double t, const EnergyReport& e) {
  return {t, e.kinetic_translational, e.kinetic_rotational, e.potential_gravity, e.elastic, e.total()};
}
}  // namespace

RunSummary run_scene(const Scene& scene, Engine& engine, const RunOptions& options) {
  RunWriter writer(options.out, options.overwrite);  // refuses to overwrite before any work is done
  writer.set_energy_columns(
      {"time", "kinetic_translational", "kinetic_rotational", "potential_gravity", "elastic", "total"});
  RunSummary summary;
  summary.initial = engine.energies();
  const int frames = std::max(1, scene.output.frames);
  writer.add_frame(engine.frame());
  writer.add_energy_row(energy_row(engine.time(), summary.initial));
  // Between frames, advance in slices so the progress display stays live on long runs.
  const int slices = 20;
  for (int k = 1; k <= frames; ++k) {
    const double t0 = scene.duration * (k - 1) / frames, t1 = scene.duration * k / frames;
    for (int s = 1; s <= slices; ++s) {
      engine.advance_to(t0 + (t1 - t0) * s / slices);
      if (options.progress) options.progress(engine.time(), scene.duration);
    }
    writer.add_frame(engine.frame());
    writer.add_energy_row(energy_row(engine.time(), engine.energies()));
  }
  summary.final = engine.energies();
  summary.diagnostics = engine.diagnostics();

  RunMetadata meta;
  meta.text["grainlab_version"] = GRAINLAB_VERSION;
  meta.text["scene_file"] = scene.path;
  meta.text["scene_text"] = scene.text;
  meta.text["scene_overrides"] = fmt::format("{}", fmt::join(scene.overrides, "\n"));
  meta.text["scene_name"] = scene.name;
  meta.text["units"] = scene.units + " (cm, g, s; 2-D masses per unit thickness)";
  meta.text["active_effects"] = fmt::format("{}", fmt::join(scene.effects.names(), ","));
  meta.text["engine"] = engine.name();
  meta.text["integrator"] = engine.integrator();
  meta.numbers["seed"] = static_cast<double>(scene.seed);
  meta.numbers["duration"] = scene.duration;
  meta.numbers["dimension"] = scene.dimension;
  writer.set_metadata(meta);
  writer.set_diagnostics(summary.diagnostics);
  writer.set_polygons(engine.polygon_shapes());
  summary.h5 = options.out;
  summary.xmf = writer.commit();
  return summary;
}

}  // namespace grainlab
