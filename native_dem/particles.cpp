#include "particles.hpp"

namespace grainlab::dem {

namespace {
template <typename F>
void for_each_array(Particles& p, F&& f) {
  for (auto* a : {&p.x, &p.y, &p.th, &p.vx, &p.vy, &p.w, &p.vx_prev, &p.vy_prev, &p.w_prev, &p.fx, &p.fy,
                  &p.tq, &p.m, &p.inv_m, &p.inertia, &p.inv_inertia, &p.r})
    f(*a);
  f(p.id);
  f(p.shape);
  f(p.mat);
}

template <typename T>
void apply_order(std::vector<T>& a, const std::vector<std::uint32_t>& order, std::vector<T>& scratch) {
  scratch.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) scratch[k] = a[order[k]];
  a.swap(scratch);
}
}  // namespace

void Particles::resize(std::size_t n) {
  for_each_array(*this, [n](auto& a) { a.resize(n); });
}

void Particles::permute(const std::vector<std::uint32_t>& order) {
  std::vector<double> sd;
  std::vector<std::int64_t> si;
  std::vector<std::int32_t> s32;
  for_each_array(*this, [&](auto& a) {
    using T = typename std::decay_t<decltype(a)>::value_type;
    if constexpr (std::is_same_v<T, double>)
      apply_order(a, order, sd);
    else if constexpr (std::is_same_v<T, std::int64_t>)
      apply_order(a, order, si);
    else
      apply_order(a, order, s32);
  });
}

}  // namespace grainlab::dem
