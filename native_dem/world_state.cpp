// Saving and restoring a world's whole state (checkpoints). A restored world continues bit for bit as
// the original would have: the neighbour-list build positions come back too, so lists are rebuilt on
// the same steps and periodic wrapping happens at the same times.
#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "parallel.hpp"
#include "world.hpp"

namespace grainlab::dem {

namespace {
// Sorts rows of `width` doubles by their first column (an id).
std::vector<double> sorted_rows(const std::vector<double>& flat, std::size_t width) {
  const std::size_t n = flat.size() / width;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    for (std::size_t c = 0; c + 1 < width; ++c)
      if (flat[a * width + c] != flat[b * width + c]) return flat[a * width + c] < flat[b * width + c];
    return false;
  });
  std::vector<double> out;
  out.reserve(flat.size());
  for (std::size_t k : order) out.insert(out.end(), flat.begin() + k * width, flat.begin() + (k + 1) * width);
  return out;
}
}  // namespace

WorldState World::save_state() const {
  WorldState s;
  s.particles = gather_particles();
  std::vector<double> build;
  for (std::size_t i = 0; i < n_own_; ++i)
    build.insert(build.end(), {double(p_.id[i]), x_build_[i], y_build_[i]});
  // A pair with a ghost is saved by both ranks with the same value: keep one (ordered a < b).
  std::vector<double> history;
  for (const SavedShear& h : save_history()) {
    const bool wall = h.b < 0;
    const std::int64_t a = wall ? h.a : std::min(h.a, h.b), b = wall ? h.b : std::max(h.a, h.b);
    history.insert(history.end(), {double(a), double(b), h.xi});
  }
  if (domain_) {
    build = parallel::gather_to_root(build);
    history = parallel::gather_to_root(history);
  }
  // The wind's tallies of the interval under way are per rank: summed here (collective).
  if (wind_) s.wind = wind_->save(domain_.has_value());
  if (domain_ && parallel::rank() != 0) return {};
  build = sorted_rows(build, 3);
  history = sorted_rows(history, 3);
  for (std::size_t k = 0; k < build.size(); k += 3) {
    s.x_build.push_back(build[k + 1]);
    s.y_build.push_back(build[k + 2]);
  }
  for (std::size_t k = 0; k < history.size(); k += 3) {
    if (k > 0 && history[k] == history[k - 3] && history[k + 1] == history[k - 2]) continue;
    const auto a = static_cast<std::int64_t>(history[k]), b = static_cast<std::int64_t>(history[k + 1]);
    s.history.push_back({shear_key(a, b), a, b, history[k + 2]});
  }
  s.t = t_, s.dt = dt_, s.dt_prev = dt_prev_, s.have_prev = have_prev_;
  s.diagnostics = diag_;
  return s;
}

void World::restore_state(const WorldState& s) {
  const Particles& q = s.particles;
  if (q.size() != s.x_build.size() || q.size() != s.y_build.size())
    throw std::runtime_error("the saved state's particle and build-position counts differ");
  // The scene built this world: its particles must be the saved ones (same ids, radii and masses).
  std::vector<std::uint64_t> total{n_own_};
  if (domain_) parallel::sum_all(total);
  if (total[0] != q.size())
    throw std::runtime_error(
        fmt::format("the saved state has {} particles, the scene {}", q.size(), total[0]));
  for (std::size_t i = 0; i < n_own_; ++i) {
    const auto it = std::lower_bound(q.id.begin(), q.id.end(), p_.id[i]);
    const std::size_t k = static_cast<std::size_t>(it - q.id.begin());
    if (it == q.id.end() || *it != p_.id[i] || q.r[k] != p_.r[i] || q.m[k] != p_.m[i])
      throw std::runtime_error(
          fmt::format("particle {} of the scene is not in the saved state as it is in the scene", p_.id[i]));
  }
  // Each rank keeps its region of the saved particles (split by count, as at the start).
  std::vector<std::uint32_t> mine;
  if (domain_) {
    std::vector<double> points;
    for (std::size_t k = 0; k < q.size(); ++k)
      points.insert(points.end(), {q.x[k], q.y[k], 1.0, double(q.id[k])});
    domain_->cut_evenly(points);
    for (std::size_t k = 0; k < q.size(); ++k)
      if (domain_->owner(q.x[k], q.y[k]) == domain_->rank) mine.push_back(static_cast<std::uint32_t>(k));
  } else {
    mine.resize(q.size());
    std::iota(mine.begin(), mine.end(), 0u);
  }
  p_ = q;
  p_.permute(mine);
  n_own_ = p_.size();
  x_build_.clear(), y_build_.clear();
  for (std::uint32_t k : mine) x_build_.push_back(s.x_build[k]), y_build_.push_back(s.y_build[k]);
  t_ = s.t, dt_ = s.dt, dt_prev_ = s.dt_prev, have_prev_ = s.have_prev;
  diag_ = s.diagnostics;
  if (wind_) wind_->restore(s.wind, !domain_ || domain_->rank == 0);
  rebuild_after_restore(s.history);
}

// A neighbour list built at the restored positions rather than at the build positions: the particles
// may move a whole skin from here before the build positions call for a rebuild, so pairs and ghosts
// are found a skin further out until then.
void World::rebuild_after_restore(std::vector<SavedShear> history) {
  extra_reach_ = skin_;
  std::sort(history.begin(), history.end());
  const std::vector<double> xb = x_build_, yb = y_build_;
  sort_owned_by_cell();
  for (std::size_t k = 0; k < n_own_; ++k) x_build_[k] = xb[order_[k]], y_build_[k] = yb[order_[k]];
  if (domain_) receive_ghosts();
  build_pair_lists();
  build_incidence();
  restore_history(history);
  ghosts_fresh_ = true;
}

namespace {
const std::vector<std::string> kParticleColumns = {
    "id",          "x",         "y",     "angle",    "vx",      "vy",     "spin",     "vx_prev",
    "vy_prev",     "spin_prev", "fx",    "fy",       "torque",  "mass",   "inv_mass", "inertia",
    "inv_inertia", "radius",    "shape", "material", "x_build", "y_build"};
const std::vector<std::string> kHistoryColumns = {"a", "b", "extension"};
}  // namespace

const std::vector<std::string> kClockColumns = {"t",
                                                "dt",
                                                "dt_prev",
                                                "have_prev",
                                                "steps",
                                                "rejected_steps",
                                                "force_evaluations",
                                                "neighbor_rebuilds",
                                                "contacts",
                                                "max_contacts",
                                                "dt_last",
                                                "dt_min_used",
                                                "dt_max_used"};

SampleTable clock_table(const std::string& name, const SavedClock& c) {
  const Diagnostics& d = c.diagnostics;
  return {name,
          "time, step and step diagnostics",
          kClockColumns,
          {{c.t, c.dt, c.dt_prev, c.have_prev ? 1.0 : 0.0, double(d.steps), double(d.rejected_steps),
            double(d.force_evaluations), double(d.neighbor_rebuilds), double(d.contacts),
            double(d.max_contacts), d.dt_last, d.dt_min_used, d.dt_max_used}}};
}

SavedClock clock_from_table(const SampleTable& ct) {
  if (ct.rows.size() != 1) throw std::runtime_error("the saved clock table must have one row");
  const std::vector<double>& c = ct.rows[0];
  SavedClock s;
  s.t = c[0], s.dt = c[1], s.dt_prev = c[2], s.have_prev = c[3] != 0;
  Diagnostics& d = s.diagnostics;
  d.steps = static_cast<std::uint64_t>(c[4]), d.rejected_steps = static_cast<std::uint64_t>(c[5]);
  d.force_evaluations = static_cast<std::uint64_t>(c[6]),
  d.neighbor_rebuilds = static_cast<std::uint64_t>(c[7]);
  d.contacts = static_cast<std::size_t>(c[8]), d.max_contacts = static_cast<std::size_t>(c[9]);
  d.dt_last = c[10], d.dt_min_used = c[11], d.dt_max_used = c[12];
  return s;
}

namespace {

// The per-particle arrays in kParticleColumns order (after the id), as member pointers.
const std::vector<std::vector<double> Particles::*>& particle_fields() {
  static const std::vector<std::vector<double> Particles::*> f = {
      &Particles::x,      &Particles::y,     &Particles::th,      &Particles::vx,
      &Particles::vy,     &Particles::w,     &Particles::vx_prev, &Particles::vy_prev,
      &Particles::w_prev, &Particles::fx,    &Particles::fy,      &Particles::tq,
      &Particles::m,      &Particles::inv_m, &Particles::inertia, &Particles::inv_inertia,
      &Particles::r};
  return f;
}
}  // namespace

std::map<std::string, std::vector<std::string>> state_table_columns(const std::string& prefix) {
  return {{prefix + "particles", kParticleColumns},
          {prefix + "history", kHistoryColumns},
          {prefix + "clock", kClockColumns},
          {prefix + "wind", {"value"}}};
}

std::vector<SampleTable> state_tables(const WorldState& s, const std::string& prefix) {
  SampleTable particles{prefix + "particles", "every particle's state, by id", kParticleColumns, {}};
  const Particles& p = s.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::vector<double> row{double(p.id[i])};
    for (auto f : particle_fields()) row.push_back((p.*f)[i]);
    row.insert(row.end(), {double(p.shape[i]), double(p.mat[i]), s.x_build[i], s.y_build[i]});
    particles.rows.push_back(std::move(row));
  }
  SampleTable history{
      prefix + "history", "committed shear springs by pair ids (b < 0: wall -1 - b)", kHistoryColumns, {}};
  for (const World::SavedShear& h : s.history) history.rows.push_back({double(h.a), double(h.b), h.xi});
  const SampleTable clock = clock_table(prefix + "clock", {s.t, s.dt, s.dt_prev, s.have_prev, s.diagnostics});
  SampleTable wind{
      prefix + "wind", "the wind of effect wind_drag (native_dem/wind.cpp: WindField::save)", {"value"}, {}};
  for (double v : s.wind) wind.rows.push_back({v});
  return {particles, history, clock, wind};
}

WorldState state_from_tables(const std::map<std::string, SampleTable>& tables, const std::string& prefix) {
  WorldState s;
  const SampleTable& pt = tables.at(prefix + "particles");
  Particles& p = s.particles;
  p.resize(pt.rows.size());
  for (std::size_t i = 0; i < pt.rows.size(); ++i) {
    const std::vector<double>& row = pt.rows[i];
    p.id[i] = static_cast<std::int64_t>(row[0]);
    for (std::size_t f = 0; f < particle_fields().size(); ++f) (p.*particle_fields()[f])[i] = row[1 + f];
    const std::size_t rest = 1 + particle_fields().size();
    p.shape[i] = static_cast<std::int32_t>(row[rest]);
    p.mat[i] = static_cast<std::int32_t>(row[rest + 1]);
    s.x_build.push_back(row[rest + 2]);
    s.y_build.push_back(row[rest + 3]);
    if (i > 0 && p.id[i] <= p.id[i - 1])
      throw std::runtime_error("the saved particles are not ordered by id");
  }
  for (const std::vector<double>& row : tables.at(prefix + "history").rows) {
    const auto a = static_cast<std::int64_t>(row[0]), b = static_cast<std::int64_t>(row[1]);
    s.history.push_back({World::shear_key(a, b), a, b, row[2]});
  }
  const SavedClock c = clock_from_table(tables.at(prefix + "clock"));
  s.t = c.t, s.dt = c.dt, s.dt_prev = c.dt_prev, s.have_prev = c.have_prev, s.diagnostics = c.diagnostics;
  if (tables.count(prefix + "wind"))
    for (const std::vector<double>& row : tables.at(prefix + "wind").rows) s.wind.push_back(row.at(0));
  return s;
}

}  // namespace grainlab::dem
