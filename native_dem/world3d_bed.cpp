// The 3-D engine's bridge to its sphere kernel (sphere_bed.*): which scenes run on it, and moving the
// bodies in and out of it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "input_error.hpp"
#include "parallel.hpp"
#include "world3d.hpp"
#include "world3d_detail.hpp"

namespace grainlab::dem {

bool World3d::sphere_kernel_eligible() const {
  if (!sphere_kernel_allowed_ || after_step_) return false;
  if (b_.size() < kCellsFrom && !decomposition_.distributed) return false;  // few bodies: the general path
  if (scene_.accuracy.integrator != Integrator::VelocityVerlet) return false;
  return std::all_of(b_.begin(), b_.end(), [](const Body3& b) { return !b.hull && b.isotropic; });
}

SphereBedSetup World3d::bed_setup() const {
  SphereBedSetup s;
  for (const PlaneSpec& p : scene_.planes)
    s.planes.push_back({p.point, p.normal}), s.plane_motion.push_back(p.motion);
  s.plane_material = plane_material_;
  s.laws = laws_;
  s.n_mat = n_mat_;
  s.contacts = effects_.has(Effect::normal_contact);
  s.friction = effects_.has(Effect::friction);
  s.rotation = effects_.has(Effect::rotation);
  s.gravity = detail3d::effective_gravity(scene_);
  s.dt = dt_;
  s.periodic_x = scene_.periodic_x;
  s.periodic_y = scene_.periodic_y;
  return s;
}

// A periodic side narrower than the sphere kernel's lists allow is the scene's mistake: named here, by its
// key (exit 2), rather than by the lists' grid when it is built.
void World3d::check_periods(double r_max) const {
  const double skin = SphereBed::kSkinPerRadius * r_max, reach = 2 * r_max + skin;
  for (const auto& [key, period] : {std::make_pair("scene.periodic_x", scene_.periodic_x),
                                    std::make_pair("scene.periodic_y", scene_.periodic_y)})
    if (period && std::floor((period->second - period->first) / reach) < SphereCells::kMinPeriodicCells)
      throw InputError(
          {scene_.path, 0}, key,
          fmt::format("the box is {:g} wide across it, less than {} neighbour cells of {:g} (the "
                      "largest sphere's diameter, {:g}, plus the skin, {:g}): make it wider",
                      period->second - period->first, SphereCells::kMinPeriodicCells, reach, 2 * r_max,
                      skin));
}

std::size_t World3d::body_of_id(std::int64_t id) const {
  const auto it = std::lower_bound(by_id_.begin(), by_id_.end(), std::make_pair(id, std::size_t{0}));
  if (it == by_id_.end() || it->first != id)
    throw std::runtime_error(fmt::format("body {} is not in the scene", id));
  return it->second;
}

void World3d::load_bed(bool spread) {
  std::vector<SphereState> spheres(b_.size());
  double r_max = 0;
  by_id_.clear();
  for (std::size_t i = 0; i < b_.size(); ++i) {
    const Body3& b = b_[i];
    SphereState& s = spheres[i];
    s.id = b.id, s.x = b.x, s.v = b.v, s.w = b.w, s.f = b.f, s.tq = b.tq, s.q = b.q;
    s.m = b.m, s.inv_i = b.inv_inertia(0, 0), s.r = b.radius, s.material = b.material, s.held = b.held;
    r_max = std::max(r_max, b.radius);
    by_id_.push_back({b.id, i});
  }
  std::sort(by_id_.begin(), by_id_.end());
  check_periods(r_max);
  bed_.load(bed_setup(), spheres, r_max);
  if (spread && decomposition_.distributed) bed_.distribute(decomposition_);
  bed_body_.clear();
  for (std::size_t slot = 0; slot < bed_.size(); ++slot) bed_body_.push_back(body_of_id(bed_.id(slot)));
  bed_loaded_ = true;
}

// This rank's spheres back into the bodies; in a distributed world rank 0 gathers everyone's.
void World3d::store_bed() {
  bed_.finish();
  bed_body_.clear();
  std::vector<double> mine;
  if (distributed()) mine.reserve(20 * bed_.size());
  bed_.each_state([&](const SphereState& st) {
    const std::size_t i = body_of_id(st.id);
    bed_body_.push_back(i);
    Body3& b = b_[i];
    b.x = st.x, b.v = st.v, b.w = st.w, b.f = st.f, b.tq = st.tq, b.q = st.q;
    if (distributed())
      mine.insert(mine.end(), {double(st.id), st.x.x(),  st.x.y(), st.x.z(), st.v.x(), st.v.y(), st.v.z(),
                               st.w.x(),      st.w.y(),  st.w.z(), st.f.x(), st.f.y(), st.f.z(), st.tq.x(),
                               st.tq.y(),     st.tq.z(), st.q.w(), st.q.x(), st.q.y(), st.q.z()});
  });
  if (!distributed()) return;
  const std::vector<double> all = parallel::gather_to_root(mine);
  for (std::size_t k = 0; k + 20 <= all.size(); k += 20) {
    const double* r = all.data() + k;
    Body3& b = b_[body_of_id(static_cast<std::int64_t>(r[0]))];
    b.x = {r[1], r[2], r[3]}, b.v = {r[4], r[5], r[6]}, b.w = {r[7], r[8], r[9]}, b.f = {r[10], r[11], r[12]};
    b.tq = {r[13], r[14], r[15]}, b.q = Quat(r[16], r[17], r[18], r[19]);
  }
}

// Each sphere's share (kinetic, rotational, gravity, and half of each pair spring, all of its planes'),
// summed in id order whatever the ranks: the same bits from any number of them.
Energies World3d::bed_energies(const Vec3& g) const {
  const std::vector<double> elastic = bed_.elastic_shares();
  std::vector<double> share;
  std::size_t k = 0;
  for (std::size_t slot = 0; slot < bed_.size(); ++slot) {
    if (bed_.ghost(slot)) continue;
    const Body3& b = b_[bed_body_[k++]];
    share.insert(share.end(),
                 {double(b.id), 0.5 * b.m * b.v.squaredNorm(),
                  effects_.has(Effect::rotation) ? 0.5 * b.w.dot(b.angular_momentum()) : 0.0,
                  -b.m * g.dot(b.x), effects_.has(Effect::normal_contact) ? elastic[slot] : 0.0});
  }
  const std::vector<double> all = distributed() ? parallel::gather_all(share) : share;
  std::vector<std::size_t> order(all.size() / 5);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return all[5 * a] < all[5 * b]; });
  Energies e;
  for (std::size_t i : order) {
    e.kinetic_translational += all[5 * i + 1];
    e.kinetic_rotational += all[5 * i + 2];
    e.potential_gravity += all[5 * i + 3];
    e.elastic += all[5 * i + 4];
  }
  return e;
}

std::size_t World3d::count_contacts() const {
  if (!distributed() || mode_ != Mode::spheres) return last_contacts_;
  std::vector<std::uint64_t> n{last_contacts_};
  parallel::sum_all(n);
  return n[0];
}

void World3d::gather_bed_state(std::vector<Vec3>& built, std::vector<SphereSpring>& springs) const {
  std::vector<double> mine;
  for (std::size_t slot = 0; slot < bed_.size(); ++slot) {
    if (bed_.ghost(slot)) continue;
    const Vec3& p = bed_.build_positions()[slot];
    mine.insert(mine.end(), {double(bed_.id(slot)), p.x(), p.y(), p.z()});
  }
  const std::vector<double> points = distributed() ? parallel::gather_to_root(mine) : mine;
  for (std::size_t k = 0; k + 4 <= points.size(); k += 4)
    built[body_of_id(static_cast<std::int64_t>(points[k]))] = {points[k + 1], points[k + 2], points[k + 3]};
  std::vector<double> held;
  for (const SphereSpring& s : bed_.springs())
    held.insert(held.end(), {double(s.a), double(s.b), s.xi.x(), s.xi.y(), s.xi.z()});
  const std::vector<double> all = distributed() ? parallel::gather_to_root(held) : held;
  springs.clear();
  for (std::size_t k = 0; k + 5 <= all.size(); k += 5)
    springs.push_back({static_cast<std::int64_t>(all[k]), static_cast<std::int64_t>(all[k + 1]),
                       Vec3(all[k + 2], all[k + 3], all[k + 4])});
  std::sort(springs.begin(), springs.end(), spring_order);
  springs.erase(
      std::unique(springs.begin(), springs.end(),
                  [](const SphereSpring& p, const SphereSpring& q) { return p.a == q.a && p.b == q.b; }),
      springs.end());
}

}  // namespace grainlab::dem
