// Saving and restoring the 3-D engine's whole state (checkpoints, velocity Verlet). The bodies carry the
// force and torque of the last evaluation (Verlet's first half kick uses them) and, on the sphere kernel,
// where the neighbour lists were built: the lists are rebuilt there on restoring, so rebuilds and
// periodic wrapping happen on the same steps as in the run that was saved, and it continues bit for bit.
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "world.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {
const std::vector<std::string> kBodyColumns = {"id", "x",  "y",  "z",  "vx",      "vy",      "vz",     "qw",
                                               "qx", "qy", "qz", "wx", "wy",      "wz",      "fx",     "fy",
                                               "fz", "tx", "ty", "tz", "x_build", "y_build", "z_build"};
// b < 0: plane -1 - b. feature: the general path's contact feature (0 on the sphere kernel).
const std::vector<std::string> kSpringColumns = {"a", "b", "feature", "xi_x", "xi_y", "xi_z", "k_s"};

}  // namespace

std::map<std::string, std::vector<std::string>> World3d::state_columns(const std::string& prefix) {
  return {{prefix + "bodies", kBodyColumns},
          {prefix + "springs", kSpringColumns},
          {prefix + "clock", kClockColumns}};
}

std::vector<SampleTable> World3d::save_state(const std::string& prefix) const {
  const bool kernel = mode_ == Mode::spheres && bed_loaded_ && bed_.list_builds() > 0;
  std::vector<Vec3> built(b_.size());
  for (std::size_t i = 0; i < b_.size(); ++i) built[i] = b_[i].x;
  std::vector<SphereSpring> bed_springs;
  if (kernel) gather_bed_state(built, bed_springs);  // collective when distributed
  SampleTable bodies{prefix + "bodies", "every body's state in the scene's order", kBodyColumns, {}};
  for (std::size_t i = 0; i < b_.size(); ++i) {
    const Body3& b = b_[i];
    bodies.rows.push_back({double(b.id), b.x.x(),  b.x.y(),      b.x.z(),      b.v.x(),     b.v.y(),
                           b.v.z(),      b.q.w(),  b.q.x(),      b.q.y(),      b.q.z(),     b.w.x(),
                           b.w.y(),      b.w.z(),  b.f.x(),      b.f.y(),      b.f.z(),     b.tq.x(),
                           b.tq.y(),     b.tq.z(), built[i].x(), built[i].y(), built[i].z()});
  }
  SampleTable springs{prefix + "springs", "shear springs held (b < 0: plane -1 - b)", kSpringColumns, {}};
  auto add = [&](double a, double b, double feature, const Vec3& xi, double k_s) {
    springs.rows.push_back({a, b, feature, xi.x(), xi.y(), xi.z(), k_s});
  };
  if (mode_ == Mode::spheres) {
    std::unordered_map<std::int64_t, int> material;
    for (const Body3& b : b_) material[b.id] = b.material;
    if (bed_loaded_)
      for (const SphereSpring& s : bed_springs) {
        const int other = s.b < 0 ? plane_material_[static_cast<std::size_t>(-1 - s.b)] : material.at(s.b);
        add(double(s.a), double(s.b), 0, s.xi, laws_[material.at(s.a) * n_mat_ + other].k_s);
      }
  } else {
    for (const auto& [key, spring] : history_)
      add(double(std::get<0>(key)), double(std::get<1>(key)), std::get<2>(key), spring.xi, spring.k_s);
  }
  return {bodies, springs, clock_table(prefix + "clock", {t_, dt_, dt_prev_, have_prev_, diag_})};
}

void World3d::restore_state(const std::map<std::string, SampleTable>& tables, const std::string& prefix) {
  const auto& rows = tables.at(prefix + "bodies").rows;
  if (rows.size() != b_.size())
    throw std::runtime_error(
        fmt::format("the saved state has {} bodies, the scene {}", rows.size(), b_.size()));
  std::unordered_map<std::int64_t, std::size_t> index;
  for (std::size_t i = 0; i < b_.size(); ++i) index[b_[i].id] = i;
  auto body_of = [&](double id) {
    const auto it = index.find(static_cast<std::int64_t>(id));
    if (it == index.end()) throw std::runtime_error(fmt::format("body {} is not in the scene", id));
    return it->second;
  };
  std::vector<Vec3> built(b_.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double>& r = rows[k];
    if (body_of(r[0]) != k) throw std::runtime_error("the saved bodies are not in the scene's order");
    Body3& b = b_[k];
    b.x = {r[1], r[2], r[3]}, b.v = {r[4], r[5], r[6]}, b.q = Quat(r[7], r[8], r[9], r[10]);
    b.w = {r[11], r[12], r[13]}, b.f = {r[14], r[15], r[16]}, b.tq = {r[17], r[18], r[19]};
    built[k] = {r[20], r[21], r[22]};
  }
  const SavedClock c = clock_from_table(tables.at(prefix + "clock"));
  t_ = c.t, dt_ = c.dt, dt_prev_ = c.dt_prev, have_prev_ = c.have_prev, diag_ = c.diagnostics;
  const auto& springs = tables.at(prefix + "springs").rows;
  mode_ = Mode::undecided;
  decide_mode();
  if (mode_ == Mode::general) {
    history_.clear();
    for (const std::vector<double>& r : springs)
      history_.append(
          {static_cast<std::int64_t>(r[0]), static_cast<std::int64_t>(r[1]), static_cast<int>(r[2])},
          {Vec3(r[3], r[4], r[5]), r[6]});
    history_.sort();
    return;
  }
  // The kernel: lists built where they were (a fresh build: no springs to carry), then the springs put
  // back into their pairs' slots.
  load_bed(false);
  std::vector<Vec3> built_by_slot(b_.size());
  for (std::size_t k = 0; k < bed_body_.size(); ++k) built_by_slot[k] = built[bed_body_[k]];
  std::vector<SphereSpring> held;
  for (const std::vector<double>& r : springs) {
    body_of(r[0]);
    if (r[1] >= 0) body_of(r[1]);
    held.push_back(
        {static_cast<std::int64_t>(r[0]), static_cast<std::int64_t>(r[1]), Vec3(r[3], r[4], r[5])});
  }
  bed_.restore(built_by_slot, held, decomposition_);
  store_bed();  // which bodies are this rank's, and rank 0's view of all
}

}  // namespace grainlab::dem
