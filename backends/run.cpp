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

Frame in_scene_units(Frame f, const Scene& scene) {
  const double L = scene.to_cgs.length, V = scene.to_cgs.velocity(), T = scene.to_cgs.time;
  f.time /= T;
  for (double& x : f.position) x /= L;
  for (double& v : f.velocity) v /= V;
  for (double& r : f.radius) r /= L;
  for (double& w : f.spin) w *= T;
  for (double& w : f.angular_velocity) w *= T;
  return f;
}

EnergyReport in_scene_units(EnergyReport e, const Scene& scene) {
  const double E = scene.to_cgs.energy();
  return {e.kinetic_translational / E, e.kinetic_rotational / E, e.potential_gravity / E, e.elastic / E};
}

ContactEventTable in_scene_units(const std::vector<ContactEvent>& events, const Scene& scene) {
  const Scene::UnitScale& u = scene.to_cgs;
  const double impulse = u.mass * u.velocity(), force = impulse / u.time;
  ContactEventTable t;
  for (const ContactEvent& e : events) {
    t.body_a.push_back(e.body_a);
    t.body_b.push_back(e.body_b);
    t.t_begin.push_back(e.t_begin / u.time);
    t.t_end.push_back(e.t_end / u.time);
    t.normal_impulse.push_back(e.normal_impulse / impulse);
    t.peak_force.push_back(e.peak_force / force);
    t.open.push_back(e.open ? 1 : 0);
  }
  return t;
}

std::string units_description(const Scene& scene) {
  const std::string mass = scene.dimension == 2 ? "; 2-D masses as in the thesis, rho pi r^2" : "";
  return scene.units == "si" ? "si (m, kg, s; energies in J" + mass + ")"
                             : "cgs (cm, g, s; energies in erg" + mass + ")";
}

RunSummary run_scene(const Scene& scene, Engine& engine, const RunOptions& options) {
  RunWriter writer(options.out, options.overwrite);  // refuses to overwrite before any work is done
  writer.set_energy_columns(
      {"time", "kinetic_translational", "kinetic_rotational", "potential_gravity", "elastic", "total"});
  RunSummary summary;
  engine.track_contacts(scene.output.contacts);
  summary.initial = in_scene_units(engine.energies(), scene);
  const int frames = std::max(1, scene.output.frames);
  const double T = scene.to_cgs.time;
  writer.add_frame(in_scene_units(engine.frame(), scene));
  writer.add_energy_row(energy_row(engine.time() / T, summary.initial));
  // Between frames, advance in slices so the progress display stays live on long runs.
  const int slices = 20;
  for (int k = 1; k <= frames; ++k) {
    const double t0 = scene.duration * (k - 1) / frames, t1 = scene.duration * k / frames;
    for (int s = 1; s <= slices; ++s) {
      engine.advance_to(t0 + (t1 - t0) * s / slices);
      if (options.progress) options.progress(engine.time() / T, scene.duration / T);
    }
    writer.add_frame(in_scene_units(engine.frame(), scene));
    writer.add_energy_row(energy_row(engine.time() / T, in_scene_units(engine.energies(), scene)));
  }
  summary.final = in_scene_units(engine.energies(), scene);
  summary.diagnostics = engine.diagnostics();

  RunMetadata meta;
  meta.text["grainlab_version"] = GRAINLAB_VERSION;
  meta.text["scene_file"] = scene.path;
  meta.text["scene_text"] = scene.text;
  meta.text["scene_overrides"] = fmt::format("{}", fmt::join(scene.overrides, "\n"));
  meta.text["scene_name"] = scene.name;
  meta.text["units"] = units_description(scene);
  meta.text["active_effects"] = fmt::format("{}", fmt::join(scene.effects.names(), ","));
  meta.text["engine"] = engine.name();
  meta.text["integrator"] = engine.integrator();
  meta.numbers["seed"] = static_cast<double>(scene.seed);
  meta.numbers["duration"] = scene.duration / T;
  meta.numbers["dimension"] = scene.dimension;
  writer.set_metadata(meta);
  writer.set_diagnostics(summary.diagnostics);
  if (scene.output.contacts) writer.set_contact_events(in_scene_units(engine.contact_events(), scene));
  std::vector<std::vector<double>> polygons = engine.polygon_shapes();
  for (auto& poly : polygons)
    for (double& x : poly) x /= scene.to_cgs.length;
  writer.set_polygons(polygons, scene.dimension);
  summary.h5 = options.out;
  summary.xmf = writer.commit();
  return summary;
}

}  // namespace grainlab
