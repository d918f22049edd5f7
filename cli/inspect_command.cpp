#include "inspect_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "h5_input.hpp"
#include "input_error.hpp"
#include "splash_file.hpp"

namespace grainlab::cli {

namespace {

std::string text_or(const std::map<std::string, std::string>& text, const std::string& key,
                    const std::string& fallback = "?") {
  const auto it = text.find(key);
  return it == text.end() ? fallback : it->second;
}

int inspect_run(const std::string& path) {
  const RunFileSummary s = read_run_file(path);
  fmt::print("{}: grainlab {} run of \"{}\" on {}\n", path, text_or(s.text, "grainlab_version"),
             text_or(s.text, "scene_name"), text_or(s.text, "engine"));
  fmt::print("  {} frames from t = {} to {} ({}), {} bodies; every dataset read and consistent\n", s.frames,
             s.first_time, s.last_time, text_or(s.text, "units"), s.bodies);
  for (const auto& [k, v] : s.diagnostics) fmt::print("  {} = {}\n", k, v);
  return 0;
}

int inspect_splash(const std::string& path) {
  // An unfinished measurement's checkpoint is a splash file too: read, and said to be unfinished.
  const saltation::SplashFile f = saltation::read_splash_file(path, true);
  std::size_t impacts = 0, rebounds = 0, ejecta = 0;
  for (const saltation::SplashCell& c : f.cells)
    impacts += c.impacts, rebounds += c.rebound.size(), ejecta += c.ejecta.size();
  fmt::print("{}: {} splash file ({}, {}-D{}), grain d = {} cm, velocities in sqrt(g d) = {:.4g} cm/s\n",
             path, text_or(f.text, "schema"), text_or(f.text, "kind"), f.dimension,
             text_or(f.text, "engine", "").empty() ? "" : ", engine " + f.text.at("engine"),
             f.grain_diameter_cm, f.velocity_scale());
  fmt::print("  grid: speeds {:.4g} sqrt(g d) x angles {:.4g} deg: {} of {} cells{}\n",
             fmt::join(f.speeds, ", "), fmt::join(f.angles_deg, ", "), f.cells.size(),
             f.speeds.size() * f.angles_deg.size(),
             f.cells.size() < f.speeds.size() * f.angles_deg.size() ? " (an unfinished measurement)" : "");
  fmt::print("  {} impacts, {} rebound rows, {} ejecta; every dataset read and checked\n", impacts, rebounds,
             ejecta);
  if (const std::string source = text_or(f.text, "source", ""); !source.empty())
    fmt::print("  source: {}\n", source);
  return 0;
}

// A height field's frames (`ripples hybrid --out`), each read and checked: one shape, finite heights.
void inspect_grid_frames(const std::string& path, std::size_t count) {
  GridFrame first, last;
  for (std::size_t k = 0; k < count; ++k) {
    last = read_grid_frame(path, k);
    if (k == 0) first = last;
    if (last.nx != first.nx || last.ny != first.ny)
      throw InputError(
          {path, 0}, "file",
          fmt::format("frame {} is {} x {}, frame 0 {} x {}", k, last.ny, last.nx, first.ny, first.nx));
  }
  if (count == 0) {
    fmt::print("  frames/: no frames\n");
    return;
  }
  fmt::print(
      "  frames/: {} height fields of {} x {} (across x along), t = {:.6g} to {:.6g}, every one read\n",
      count, first.ny, first.nx, first.time, last.time);
}

// Two spaces per level of a name within the file ("run/transport/grains": three levels).
std::string indent_of(const std::string& name) {
  return std::string(2 + 2 * static_cast<std::size_t>(std::count(name.begin(), name.end(), '/')), ' ');
}

// A group of frames, read as frames rather than listed: a hybrid run's height fields ("frames") or a run
// checkpoint's frames ("run/frames").
bool is_frames(const std::string& name) {
  return name == "frames" || (name.size() > 7 && name.compare(name.size() - 7, 7, "/frames") == 0);
}

// A run's frames kept in a checkpoint, each read with its datasets checked against each other.
void inspect_run_frames(const std::string& path, const std::string& group, std::size_t count) {
  std::size_t bodies = 0;
  double first = 0, last = 0;
  read_frames(path, "/" + group, count, [&](const Frame& f) {
    if (bodies == 0) first = f.time;
    last = f.time, bodies = f.id.size();
  });
  fmt::print(
      "{}{}/: {} frames from t = {:.6g} to {:.6g}, {} bodies in the last; every dataset read and "
      "consistent\n",
      indent_of(group), group, count, first, last, bodies);
}

// Every object under `prefix` ("" for the top), by its full name ("run/transport/grains"), groups opened in
// turn (a checkpoint keeps its tables in groups).
void collect_objects(const std::string& path, const std::string& prefix,
                     const std::map<std::string, H5Object>& here, std::map<std::string, H5Object>& all) {
  for (const auto& [name, o] : here) {
    const std::string full = prefix + name;
    all[full] = o;
    if (!o.dataset && !is_frames(full)) collect_objects(path, full + "/", group_objects(path, full), all);
  }
}

int inspect_tables(const std::string& path, const TableFile& meta,
                   const std::map<std::string, H5Object>& objects) {
  fmt::print("{}: grainlab {} file: {}\n", path, text_or(meta.metadata, "grainlab_version"),
             text_or(meta.metadata, "model", text_or(meta.metadata, "kind", "tables")));
  std::map<std::string, H5Object> all;
  collect_objects(path, "", objects, all);
  // Every table at once, each checked against its own columns.
  std::map<std::string, std::vector<std::string>> wanted;
  for (const auto& [name, o] : all)
    if (o.table) wanted[name] = {};
  const TableFile file = read_sample_tables(path, wanted);
  for (const auto& [name, o] : all) {
    const std::string indent = indent_of(name);
    if (!o.dataset && name == "frames") {
      inspect_grid_frames(path, o.members);
    } else if (!o.dataset && is_frames(name)) {
      inspect_run_frames(path, name, o.members);
    } else if (!o.dataset) {
      fmt::print("{}{}/: a group of {}\n", indent, name, o.members);
    } else if (!o.table) {
      fmt::print("{}{}: a dataset (not read)\n", indent, name);
    } else {
      const SampleTable& t = file.tables.at(name);
      fmt::print("{}{}: {} row{} x {} column{}{}{}\n", indent, name, t.rows.size(),
                 t.rows.size() == 1 ? "" : "s", t.columns.size(), t.columns.size() == 1 ? "" : "s",
                 t.description.empty() ? "" : ": ", t.description);
    }
  }
  fmt::print("  {} table{} read and checked against {} columns\n", wanted.size(),
             wanted.size() == 1 ? "" : "s", wanted.size() == 1 ? "its" : "their");
  return 0;
}

}  // namespace

int inspect_command(const std::string& path) {
  const std::map<std::string, H5Object> objects = root_objects(path);  // (InputError if not HDF5)
  const TableFile meta = read_sample_tables(path, {});
  if (text_or(meta.metadata, "schema", "") == saltation::kSplashSchema) return inspect_splash(path);
  // `grainlab run`'s layout: frames and an energy table, the scene named at the root.
  if (objects.count("frames") && meta.metadata.count("scene_name")) return inspect_run(path);
  if (!meta.metadata.count("grainlab_version"))
    throw InputError(
        {path, 0}, "file",
        "is HDF5 but not a file grainlab wrote (no grainlab_version attribute, no splash schema)");
  return inspect_tables(path, meta, objects);
}

}  // namespace grainlab::cli
