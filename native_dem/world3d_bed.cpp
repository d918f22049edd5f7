// The 3-D engine's bridge to its sphere kernel (sphere_bed.*): which scenes run on it, and moving the
// bodies in and out of it.
#include <algorithm>
#include <numeric>

#include "world3d.hpp"
#include "world3d_detail.hpp"

namespace grainlab::dem {

bool World3d::sphere_kernel_eligible() const {
  if (!sphere_kernel_allowed_ || after_step_ || b_.size() < kCellsFrom) return false;
  if (scene_.accuracy.integrator != Integrator::VelocityVerlet) return false;
  return std::all_of(b_.begin(), b_.end(), [](const Body3& b) { return !b.hull && b.isotropic; });
}

SphereBedSetup World3d::bed_setup() const {
  SphereBedSetup s;
  s.planes = planes_;
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

void World3d::load_bed() {
  std::vector<SphereState> spheres(b_.size());
  double r_max = 0;
  for (std::size_t i = 0; i < b_.size(); ++i) {
    const Body3& b = b_[i];
    SphereState& s = spheres[i];
    s.id = b.id, s.x = b.x, s.v = b.v, s.w = b.w, s.f = b.f, s.tq = b.tq, s.q = b.q;
    s.m = b.m, s.inv_i = b.inv_inertia(0, 0), s.r = b.radius, s.material = b.material;
    r_max = std::max(r_max, b.radius);
  }
  bed_.load(bed_setup(), spheres, r_max);
  bed_body_.resize(b_.size());
  std::iota(bed_body_.begin(), bed_body_.end(), 0);
  std::sort(bed_body_.begin(), bed_body_.end(),
            [&](std::size_t a, std::size_t b) { return b_[a].id < b_[b].id; });
  bed_loaded_ = true;
}

void World3d::store_bed() {
  bed_.finish();
  const std::vector<SphereState> s = bed_.states();
  for (std::size_t k = 0; k < s.size(); ++k) {
    Body3& b = b_[bed_body_[k]];
    b.x = s[k].x, b.v = s[k].v, b.w = s[k].w, b.f = s[k].f, b.tq = s[k].tq, b.q = s[k].q;
  }
}

}  // namespace grainlab::dem
