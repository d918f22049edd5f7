#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <optional>

#include "engine.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"

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

namespace {

const std::vector<std::string> kEnergyColumns = {
    "time", "kinetic_translational", "kinetic_rotational", "potential_gravity", "elastic", "total"};
const std::vector<std::string> kProgressColumns = {"frames_done", "kinetic_translational",
                                                   "kinetic_rotational", "potential_gravity", "elastic"};
// 2: the frames are HDF5 groups copied from the streamed run file (1 held them as a table, 2-D only).
constexpr const char* kCheckpointKind = "grainlab checkpoint 2";
constexpr const char* kCheckpointFrames = "/run/frames";

std::string joined_overrides(const Scene& scene) {
  return fmt::format("{}", fmt::join(scene.overrides, "\n"));
}

// A checkpoint carries the engine's state, the energy rows and the frames written so far (copied from
// the streamed run file), so a restarted run's file holds every frame.
void write_checkpoint(const std::string& path, const Scene& scene, const Engine& engine,
                      const std::vector<SampleTable>& state, RunWriter& writer,
                      const std::vector<std::vector<double>>& energy, int frames_done,
                      const EnergyReport& initial) {
  SampleTable energy_table{"run/energy", "the energy rows written so far", kEnergyColumns, energy};
  SampleTable progress{"run/progress",
                       "frames done and the initial energies",
                       kProgressColumns,
                       {{double(frames_done), initial.kinetic_translational, initial.kinetic_rotational,
                         initial.potential_gravity, initial.elastic}}};
  std::vector<SampleTable> tables = {energy_table, progress};
  tables.insert(tables.end(), state.begin(), state.end());
  write_sample_tables(path, tables,
                      {{"kind", kCheckpointKind},
                       {"grainlab_version", GRAINLAB_VERSION},
                       {"scene_file", scene.path},
                       {"scene_text", scene.text},
                       {"scene_overrides", joined_overrides(scene)},
                       {"engine", engine.name()},
                       {"integrator", engine.integrator()},
                       {"frames", std::to_string(scene.output.frames)}},
                      [&](std::int64_t file) { writer.copy_frames(file, kCheckpointFrames); });
}

// Reads a checkpoint and puts the engine, the energy rows and (when writing) the frames back; returns the
// frames done. A file from another scene, engine or version, or a damaged one, is refused with InputError.
int restore_checkpoint(const std::string& path, const Scene& scene, Engine& engine, RunWriter* writer,
                       std::vector<std::vector<double>>& energy, EnergyReport& initial) {
  auto wanted = engine.state_columns();
  wanted["run/energy"] = kEnergyColumns;
  wanted["run/progress"] = kProgressColumns;
  const TableFile file = read_sample_tables(path, wanted);
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--restart", why); };
  auto meta = [&](const char* key) {
    auto it = file.metadata.find(key);
    return it == file.metadata.end() ? std::string() : it->second;
  };
  if (meta("kind") != kCheckpointKind) refuse("is not a grainlab checkpoint (kind \"" + meta("kind") + "\")");
  if (meta("grainlab_version") != GRAINLAB_VERSION)
    refuse("was written by grainlab " + meta("grainlab_version") + ", this is " + GRAINLAB_VERSION);
  if (meta("scene_text") != scene.text)
    refuse("was written for a different scene (" + meta("scene_file") + ")");
  if (meta("scene_overrides") != joined_overrides(scene))
    refuse(fmt::format("was written with other --set overrides (\"{}\"; this run: \"{}\")",
                       meta("scene_overrides"), joined_overrides(scene)));
  if (meta("engine") != engine.name() || meta("integrator") != engine.integrator())
    refuse("was written by the " + meta("engine") + " engine [" + meta("integrator") + "]");
  const auto& progress = file.tables.at("run/progress").rows;
  if (progress.size() != 1) refuse("has no progress row");
  const int done = static_cast<int>(progress[0][0]);
  if (done < 0 || done > scene.output.frames) refuse("is at an impossible frame");
  initial = {progress[0][1], progress[0][2], progress[0][3], progress[0][4]};
  energy = file.tables.at("run/energy").rows;
  if (energy.size() != static_cast<std::size_t>(done) + 1)
    refuse("has a different number of energy rows and frames");
  try {
    engine.restore_state(file.tables);
  } catch (const std::runtime_error& e) {
    refuse(std::string("does not fit this scene: ") + e.what());
  }
  if (writer)
    read_frames(path, kCheckpointFrames, static_cast<std::size_t>(done) + 1,
                [&](const Frame& f) { writer->add_frame(f); });
  return done;
}

}  // namespace

RunSummary run_scene(const Scene& scene, Engine& engine, const RunOptions& options) {
  // Every option that writes or reads a checkpoint is checked here, before any work, and the message
  // names the one given (a run stopped at a frame is only worth stopping if it can be continued).
  const char* asked = !options.restart.empty()       ? "--restart"
                      : options.stop_after_frame > 0 ? "--stop-after-frame"
                      : options.checkpoint_every > 0 ? "--checkpoint-every"
                                                     : nullptr;
  if (asked && !engine.checkpointable())
    throw InputError({asked, 0}, engine.name(),
                     "checkpoints are written by the native engine for 2-D disc scenes and for 3-D scenes "
                     "under integrator \"verlet\" only so far");
  if (asked && scene.output.contacts)
    throw InputError({asked, 0}, "contacts",
                     "a run recording contact events ([output] contacts) cannot be checkpointed yet");
  // Frames stream into the writer's temporary file as they are taken. It refuses to overwrite before any
  // work is done; a run stopped at a frame keeps its frames only in the checkpoint (the temporary goes).
  std::optional<RunWriter> writer;
  if (options.write) writer.emplace(options.out, options.overwrite || options.stop_after_frame > 0);
  RunWriter* const out = writer ? &*writer : nullptr;
  RunSummary summary;
  engine.track_contacts(scene.output.contacts);
  const int frames = std::max(1, scene.output.frames);
  const double T = scene.to_cgs.time;
  std::vector<std::vector<double>> energy;
  // engine.frame() is collective in a distributed engine: every rank takes it, rank 0 writes it.
  auto take_frame = [&] {
    const Frame f = in_scene_units(engine.frame(), scene);
    if (out) out->add_frame(f);
  };
  int start = 0;
  if (!options.restart.empty()) {
    start = restore_checkpoint(options.restart, scene, engine, out, energy, summary.initial);
    summary.restarted_from_frame = start;
  } else {
    summary.initial = in_scene_units(engine.energies(), scene);
    take_frame();
    energy.push_back(energy_row(engine.time() / T, summary.initial));
  }
  // Between frames, advance in slices so the progress display stays live on long runs.
  const int slices = 20;
  for (int k = start + 1; k <= frames; ++k) {
    const double t0 = scene.duration * (k - 1) / frames, t1 = scene.duration * k / frames;
    for (int s = 1; s <= slices; ++s) {
      engine.advance_to(t0 + (t1 - t0) * s / slices);
      if (options.progress) options.progress(engine.time() / T, scene.duration / T);
    }
    take_frame();
    energy.push_back(energy_row(engine.time() / T, in_scene_units(engine.energies(), scene)));
    const bool stop = k == options.stop_after_frame;
    if ((options.checkpoint_every > 0 && k % options.checkpoint_every == 0 && k < frames) || stop) {
      const std::vector<SampleTable> state = engine.save_state();  // collective
      if (out) write_checkpoint(options.checkpoint, scene, engine, state, *out, energy, k, summary.initial);
    }
    if (stop) {
      summary.stopped = true;
      return summary;
    }
  }
  summary.final = in_scene_units(engine.energies(), scene);
  summary.diagnostics = engine.diagnostics();
  if (!writer) return summary;
  writer->set_energy_columns(kEnergyColumns);
  for (const auto& row : energy) writer->add_energy_row(row);

  RunMetadata meta;
  meta.text["grainlab_version"] = GRAINLAB_VERSION;
  meta.text["scene_file"] = scene.path;
  meta.text["scene_text"] = scene.text;
  meta.text["scene_overrides"] = joined_overrides(scene);
  meta.text["scene_name"] = scene.name;
  meta.text["units"] = units_description(scene);
  meta.text["active_effects"] = fmt::format("{}", fmt::join(scene.effects.names(), ","));
  meta.text["engine"] = engine.name();
  meta.text["integrator"] = engine.integrator();
  meta.numbers["seed"] = static_cast<double>(scene.seed);
  meta.numbers["duration"] = scene.duration / T;
  meta.numbers["dimension"] = scene.dimension;
  meta.numbers["mpi_ranks"] = engine.ranks();
  meta.numbers["restarted_from_frame"] = summary.restarted_from_frame;
  writer->set_metadata(meta);
  writer->set_diagnostics(summary.diagnostics);
  if (scene.output.contacts) writer->set_contact_events(in_scene_units(engine.contact_events(), scene));
  std::vector<std::vector<double>> polygons = engine.polygon_shapes();
  for (auto& poly : polygons)
    for (double& x : poly) x /= scene.to_cgs.length;
  writer->set_polygons(polygons, scene.dimension);
  summary.h5 = options.out;
  summary.xmf = writer->commit();
  return summary;
}

}  // namespace grainlab
