// A sand-gun run's checkpoint: the settled bed (its spheres, exactly) and every impact finished so far, or,
// while the bed is being built, its spheres after the last finished stage of the build. Building a
// 20,000-sphere bed takes an hour or more and each impact on it a minute or two, so a long run keeps both
// and continues from them. Impact i of a row depends only on the bed, the row and (seed, i),
// so impacts found in the file are the ones the run would compute: a continued run gives the same numbers
// as one that never stopped, and may ask for more runs or other rows than the first did. A bed of irregular
// grains also keeps each grain's hull (vertices in its body frame, and faces), since its shapes came from
// a random pour.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "h5_input.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "sand_gun3d.hpp"
#include "world3d.hpp"

namespace grainlab::validation {

namespace {

constexpr const char* kKind = "grainlab-sand-gun-checkpoint/2";
const std::vector<std::string> kSphereColumns = {"id",  "radius", "mass", "i00", "i01", "i02",     "i10",
                                                 "i11", "i12",    "i20",  "i21", "i22", "x",       "y",
                                                 "z",   "qw",     "qx",   "qy",  "qz",  "material"};
// Irregular grains' hulls: a row per vertex, and a row per corner of each face, in order.
const std::vector<std::string> kHullVertexColumns = {"grain", "x", "y", "z"};
const std::vector<std::string> kHullFaceColumns = {"grain", "face", "vertex"};
constexpr const char* kStageRuns = "stage/runs_done";
const std::vector<std::string> kBuildColumns = {"removed",       "probes", "deep_movers",
                                                "build_seconds", "stage",  "finished"};
const std::vector<std::string> kImpactColumns = {
    "row",      "run", "x_impact", "y_impact",       "z_impact",  "rebounded",
    "vx",       "vy",  "vz",       "incident_speed", "alpha_deg", "incident_mass",
    "bed_mass", "g",   "steps",    "wall_seconds"};
const std::vector<std::string> kEjectumColumns = {"impact", "id", "mass", "x0",        "y0",  "z0",
                                                  "vx",     "vy", "vz",   "vz_launch", "time"};

// Everything that decides the bed and the impacts: the bed's spec and the impacts' seed (not the rows or
// the number of runs, which a continued run may change).
std::string fingerprint(const Bed3dSpec& s, std::uint64_t seed, const std::string& impacts_of) {
  std::string f = fmt::format(
      "spheres {} bed_seed {} seed {} width {:.17g} depth {:.17g} radius {:.17g} spread {:.17g} density "
      "{:.17g} k_n {:.17g} restitution {:.17g} mu {:.17g} settle {:.17g} time_scale {:.17g}",
      s.count, s.seed, seed, s.width, s.depth, s.radius, s.radius_spread, s.density, s.k_n, s.restitution,
      s.mu, s.settle_time, s.time_scale);
  // (Added only when set, so a loose sphere bed's checkpoint keeps the fingerprint it was written with.)
  if (s.dense()) f += " preparation dense";
  if (s.polyhedra) f += " polyhedra";
  if (s.max_probes != Bed3dSpec{}.max_probes) f += fmt::format(" max_probes {}", s.max_probes);
  if (!impacts_of.empty()) f += " impacts " + impacts_of;
  return f;
}

std::vector<double> sphere_row(const Body3Spec& b) {
  std::vector<double> r{static_cast<double>(b.id), b.radius, b.mass};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.push_back(b.inertia(i, j));
  const Quat& q = b.orientation;
  r.insert(r.end(), {b.position.x(), b.position.y(), b.position.z(), q.w(), q.x(), q.y(), q.z(),
                     static_cast<double>(b.material)});
  return r;
}

Body3Spec sphere_of(const std::vector<double>& r) {
  Body3Spec b;
  b.id = static_cast<std::int64_t>(r[0]), b.radius = r[1], b.mass = r[2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b.inertia(i, j) = r[static_cast<std::size_t>(3 + 3 * i + j)];
  b.position = Vec3(r[12], r[13], r[14]);
  b.orientation = Quat(r[15], r[16], r[17], r[18]);
  b.material = static_cast<int>(r[19]);
  return b;
}

// The hulls of a bed's irregular grains, as rows of the two hull tables.
void add_hulls(const std::vector<Body3Spec>& bodies, SampleTable& vertices, SampleTable& faces) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body3Spec& b = bodies[i];
    if (b.shape != Body3Spec::Shape::Polyhedron) continue;
    const double grain = static_cast<double>(i);
    for (const Vec3& v : b.hull.vertices) vertices.rows.push_back({grain, v.x(), v.y(), v.z()});
    for (std::size_t f = 0; f < b.hull.faces.size(); ++f)
      for (int v : b.hull.faces[f])
        faces.rows.push_back({grain, static_cast<double>(f), static_cast<double>(v)});
  }
}

// Gives every body its hull back from the two tables (every grain of an irregular bed has one); an empty
// string, or what is wrong with them.
std::string put_hulls(const TableFile& file, std::vector<Body3Spec>& bodies) {
  const std::size_t n = bodies.size();
  auto index = [](double v, std::size_t limit) {  // a whole number below limit, or limit (bad)
    return std::isfinite(v) && v >= 0 && v == std::floor(v) && v < static_cast<double>(limit)
               ? static_cast<std::size_t>(v)
               : limit;
  };
  std::vector<std::vector<Vec3>> vertices(n);
  std::vector<std::vector<std::vector<int>>> faces(n);
  for (const auto& r : file.tables.at("bed/hull_vertices").rows) {
    const std::size_t g = index(r[0], n);
    if (g == n || !std::all_of(r.begin() + 1, r.end(), [](double v) { return std::isfinite(v); }))
      return "a hull vertex of no grain, or not a number";
    vertices[g].emplace_back(r[1], r[2], r[3]);
  }
  for (const auto& r : file.tables.at("bed/hull_faces").rows) {
    const std::size_t g = index(r[0], n);
    if (g == n) return "a hull face of no grain";
    std::vector<std::vector<int>>& f = faces[g];
    const std::size_t face = index(r[1], f.size() + 1), vertex = index(r[2], vertices[g].size());
    if (face == f.size() + 1 || vertex == vertices[g].size() || face + 1 < f.size())
      return fmt::format("grain {} has a face corner out of order or of no vertex", g);
    if (face == f.size()) f.emplace_back();
    f.back().push_back(static_cast<int>(vertex));
  }
  for (std::size_t g = 0; g < n; ++g) {
    Polyhedron hull;
    if (const std::string why = make_polyhedron(vertices[g], faces[g], hull); !why.empty())
      return fmt::format("grain {}: {}", g, why);
    bodies[g].shape = Body3Spec::Shape::Polyhedron;
    bodies[g].hull = std::move(hull);
  }
  return "";
}

// The stage a build was part-way through when the checkpoint was written (see write_sand_gun_checkpoint):
// its finished runs (each sphere's state finite, the runs numbered in order) and the world of the run
// under way, whose fit to the stage is checked when the stage comes to it.
template <class Refuse>
void read_stage_under_way(const TableFile& file, const std::string& path, Bed3dBuild& b, Refuse refuse) {
  const auto it = file.metadata.find("stage_under_way");
  const std::string kind = it == file.metadata.end() ? "no" : it->second;
  if (kind == "no") return;
  if (kind != "runs" && kind != "world") refuse("says its stage under way is '" + kind + "'");
  std::map<std::string, std::vector<std::string>> wanted = {{kStageRuns, kStageRunColumns}};
  if (kind == "world") wanted.merge(dem::World3d::state_columns(kStageWorld));
  TableFile stage;
  try {
    stage = read_sample_tables(path, wanted);
  } catch (const InputError& e) {
    refuse("has a damaged stage under way: " + e.message());
  }
  for (const auto& [name, t] : stage.tables)  // (ids and planes are checked against the stage's bed later)
    for (const auto& r : t.rows)
      if (!std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); }))
        refuse(fmt::format("has a damaged {} in its stage under way", name));
  b.runs_done = stage.tables.at(kStageRuns);
  double run = 0;
  for (const auto& r : b.runs_done.rows) {
    if (std::abs(Quat(r[4], r[5], r[6], r[7]).norm() - 1) > 1e-9)
      refuse(fmt::format("has a damaged sphere in its stage's run {}", r[0]));
    if (r[0] != run && r[0] != run + 1) refuse("has its stage's runs out of order");
    run = r[0];
  }
  if (!b.runs_done.rows.empty() && b.runs_done.rows.front()[0] != 0)
    refuse("has its stage's runs out of order");
  stage.tables.erase(kStageRuns);
  b.run_under_way = std::move(stage.tables);
}

}  // namespace

void write_sand_gun_checkpoint(const std::string& path, const SandGunProgress& p, std::uint64_t seed,
                               const std::string& impacts_of) {
  // A built bed, or the spheres of a build still under way.
  const bool built = !p.bed.scene.bodies3d.empty();
  SampleTable spheres{
      "bed/spheres", "the bed's spheres, at rest (after `stage` stages of its build)", kSphereColumns, {}};
  for (const Body3Spec& b : built ? p.bed.scene.bodies3d : p.build.bodies)
    spheres.rows.push_back(sphere_row(b));
  // One record of the build, whichever holds it: a finished bed carries its own.
  const Bed3dBuild record = built ? build_record(p.bed) : p.build;
  const std::vector<double> counts{
      static_cast<double>(record.removed),     static_cast<double>(record.probes),
      static_cast<double>(record.deep_movers), record.seconds,
      static_cast<double>(record.stage),       record.finished ? 1.0 : 0.0};
  SampleTable build{
      "bed/build", "how the bed was made, and whether its build is finished", kBuildColumns, {counts}};
  SampleTable impacts{"impacts", "each finished impact: its row (1-9) and run index", kImpactColumns, {}};
  SampleTable ejecta{"ejecta", "each impact's ejecta (impact: its row in `impacts`)", kEjectumColumns, {}};
  for (const auto& [key, r] : p.done) {
    const std::vector<double> w = impact3d_row(r);
    std::vector<double> head{static_cast<double>(key.first), static_cast<double>(key.second)};
    head.insert(head.end(), w.begin(), w.begin() + kImpact3dHead);
    const double index = static_cast<double>(impacts.rows.size());
    impacts.rows.push_back(std::move(head));
    for (std::size_t k = 0; k < r.ejecta.size() && k < kMaxEjecta; ++k) {
      const auto* e = w.data() + kImpact3dHead + k * kImpact3dPerEjectum;
      std::vector<double> row{index};
      row.insert(row.end(), e, e + kImpact3dPerEjectum);
      ejecta.rows.push_back(std::move(row));
    }
  }
  std::vector<SampleTable> tables = {spheres, build, impacts, ejecta};
  if (p.bed.spec.polyhedra) {
    SampleTable vertices{"bed/hull_vertices",
                         "each irregular grain's hull: its vertices in its body frame (cm)",
                         kHullVertexColumns,
                         {}};
    SampleTable faces{"bed/hull_faces",
                      "each irregular grain's hull: the corners of each face, in order",
                      kHullFaceColumns,
                      {}};
    add_hulls(built ? p.bed.scene.bodies3d : p.build.bodies, vertices, faces);
    tables.push_back(std::move(vertices)), tables.push_back(std::move(faces));
  }
  // A stage part-way through: its finished runs and the world of the run under way (a key of the root
  // says so, so that checkpoints written between stages, and before these tables existed, still read).
  const bool under_way = !built && (!p.build.runs_done.rows.empty() || !p.build.run_under_way.empty());
  if (under_way) {
    SampleTable done = p.build.runs_done;
    done.name = kStageRuns, done.columns = kStageRunColumns;
    done.description = "how each finished run of the stage under way left the spheres";
    tables.push_back(std::move(done));
    for (const auto& [name, t] : p.build.run_under_way) tables.push_back(t);
  }
  write_sample_tables(
      path, tables,
      {{"kind", kKind},
       {"grainlab_version", GRAINLAB_VERSION},
       {"options", fingerprint(p.bed.spec, seed, impacts_of)},
       {"stage_under_way", under_way ? (p.build.run_under_way.empty() ? "runs" : "world") : "no"}});
}

std::optional<SandGunProgress> read_sand_gun_checkpoint(const std::string& path, const Bed3dSpec& spec,
                                                        std::uint64_t seed, const std::string& impacts_of) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--checkpoint", why); };
  const bool zone = impacts_of.rfind(kActiveZoneKey, 0) == 0;  // a sand gun's zone (sand_gun_impacts_of)
  TableFile file;
  try {
    std::map<std::string, std::vector<std::string>> wanted = {{"bed/spheres", kSphereColumns},
                                                              {"bed/build", kBuildColumns},
                                                              {"impacts", kImpactColumns},
                                                              {"ejecta", kEjectumColumns}};
    if (spec.polyhedra)
      wanted.insert({{"bed/hull_vertices", kHullVertexColumns}, {"bed/hull_faces", kHullFaceColumns}});
    file = read_sample_tables(path, wanted);
    // A built bed with no impacts yet serves impacts of any kind: its fingerprint need only match the bed's.
    const std::string bed_only = fingerprint(spec, seed, {});
    const auto options = file.metadata.find("options");
    const auto build = file.tables.find("bed/build");
    if (options != file.metadata.end() && file.tables.at("impacts").rows.empty() &&
        build != file.tables.end() && build->second.rows.size() == 1 && build->second.rows[0].size() > 5 &&
        build->second.rows[0][5] == 1 &&
        (options->second == bed_only || options->second.rfind(bed_only + " impacts ", 0) == 0))
      file.metadata["options"] = fingerprint(spec, seed, impacts_of);
    require_checkpoint(
        file, path, kKind, impacts_of.empty() || zone ? "sand-gun checkpoint" : "impact checkpoint",
        fingerprint(spec, seed, impacts_of),
        impacts_of.empty() || zone
            ? "was written for another bed, seed or active zone (--spheres, --bed-seed, --stiffness, "
              "--seed, --active-zone): pass the ones it was started with, or another --checkpoint"
            : "was written for another bed, seed, case or engine: pass the options it was "
              "started with (only --runs may change), or another --checkpoint");
  } catch (const InputError& e) {
    refuse(e.message());
  }
  std::vector<Body3Spec> bodies;
  for (const auto& r : file.tables.at("bed/spheres").rows) {
    bodies.push_back(sphere_of(r));
    const Body3Spec& b = bodies.back();
    const bool finite = std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); });
    if (!finite || !(b.radius > 0) || !(b.mass > 0) || std::abs(b.orientation.norm() - 1) > 1e-9 ||
        b.id != static_cast<std::int64_t>(bodies.size() - 1))
      refuse(fmt::format("bed sphere {} is damaged", bodies.size() - 1));
  }
  if (spec.polyhedra)
    if (const std::string why = put_hulls(file, bodies); !why.empty()) refuse("holds a damaged hull: " + why);
  const auto& build = file.tables.at("bed/build").rows;
  if (build.size() != 1 || !std::all_of(build[0].begin(), build[0].end(), [](double v) { return v >= 0; }) ||
      (build[0][5] != 0 && build[0][5] != 1) || build[0][4] != std::floor(build[0][4]) || build[0][4] > 1000)
    refuse("has no record of how its bed was built");
  SandGunProgress p;
  Bed3dBuild& b = p.build;
  b.removed = static_cast<std::size_t>(build[0][0]), b.probes = static_cast<std::size_t>(build[0][1]);
  b.deep_movers = static_cast<std::size_t>(build[0][2]), b.seconds = build[0][3];
  b.stage = static_cast<int>(build[0][4]), b.finished = build[0][5] == 1;
  if (bodies.empty() && (b.finished || b.stage > 0)) refuse("holds no bed");  // (none yet: inside the pour)
  if (!b.finished) {
    b.bodies = std::move(bodies);
    if (!file.tables.at("impacts").rows.empty()) refuse("has impacts on a bed still being built");
    read_stage_under_way(file, path, b, refuse);
    return p;
  }
  try {
    p.bed = bed3d_from_bodies(spec, std::move(bodies));
  } catch (const std::exception& e) {
    refuse(fmt::format("holds a bed that does not fit its box ({})", e.what()));
  }
  keep_build_record(p.bed, b);
  const auto& heads = file.tables.at("impacts").rows;
  std::vector<std::vector<double>> packed;
  for (const auto& h : heads) {
    std::vector<double> w(h.begin() + 2, h.end());
    w.resize(kImpact3dHead + kMaxEjecta * kImpact3dPerEjectum, std::numeric_limits<double>::quiet_NaN());
    packed.push_back(std::move(w));
  }
  std::vector<std::size_t> filled(heads.size(), 0);
  for (const auto& e : file.tables.at("ejecta").rows) {
    const double at = e[0];
    if (!(at >= 0 && at < static_cast<double>(heads.size())) || at != std::floor(at))
      refuse("has an ejectum of no impact");
    const auto i = static_cast<std::size_t>(at);
    if (filled[i] == kMaxEjecta) refuse("has more ejecta for one impact than a run keeps");
    std::copy(e.begin() + 1, e.end(),
              packed[i].begin() + static_cast<long>(kImpact3dHead + filled[i]++ * kImpact3dPerEjectum));
  }
  for (std::size_t i = 0; i < heads.size(); ++i) {
    const double row = heads[i][0], run = heads[i][1];
    if (!(row >= 1 && row <= 9 && run >= 0 && run == std::floor(run) && row == std::floor(row)))
      refuse(fmt::format("has an impact of row {} run {}", row, run));
    p.done[{static_cast<std::size_t>(row), static_cast<std::size_t>(run)}] = impact3d_from_row(packed[i]);
  }
  return p;
}

}  // namespace grainlab::validation
