// A distributed world: the initial split into slabs, migration of particles (with their shear
// history) between ranks at each neighbour-list rebuild, ghost copies of the neighbours' particles,
// their per-step update, and the periodic re-split that evens out the load.
#include "domain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "parallel.hpp"
#include "world.hpp"

namespace grainlab::dem {

int Domain::owner(double x, double y) const {
  const int ix = static_cast<int>(std::upper_bound(xcut.begin(), xcut.end(), x) - xcut.begin());
  const int iy = static_cast<int>(std::upper_bound(ycut.begin(), ycut.end(), y) - ycut.begin());
  return iy * px + ix;
}

double Domain::distance_to_region(double x, double y, int q) const {
  auto gap = [](double v, double a, double b) { return v < a ? a - v : (v >= b ? v - b : 0.0); };
  const double a = x_lo(q % px), b = x_hi(q % px);
  double gx = gap(x, a, b);
  if (periodic) gx = std::min({gx, gap(x - period, a, b), gap(x + period, a, b)});
  return std::hypot(gx, gap(y, y_lo(q / px), y_hi(q / px)));
}

double Domain::distance_to_own_edge(double x, double y) const {
  const int ix = rank % px, iy = rank / px;
  return std::min({x - x_lo(ix), x_hi(ix) - x, y - y_lo(iy), y_hi(iy) - y});
}

void Domain::cut_evenly(const std::vector<double>& xy_w_id) {
  std::vector<double> xs, ys;
  for (std::size_t k = 0; k + 3 < xy_w_id.size(); k += 4) {
    xs.insert(xs.end(), {xy_w_id[k], xy_w_id[k + 2], xy_w_id[k + 3]});
    ys.insert(ys.end(), {xy_w_id[k + 1], xy_w_id[k + 2], xy_w_id[k + 3]});
  }
  xcut = weighted_cuts(xs, px, xshare);
  ycut = weighted_cuts(ys, py, yshare);
}

namespace {
// Every per-particle array, as doubles (ids, shapes and materials are exact in a double).
constexpr std::size_t kFields = 20;

void pack(const Particles& p, std::size_t i, std::vector<double>& out) {
  for (const auto* a : {&p.x, &p.y, &p.th, &p.vx, &p.vy, &p.w, &p.vx_prev, &p.vy_prev, &p.w_prev, &p.fx,
                        &p.fy, &p.tq, &p.m, &p.inv_m, &p.inertia, &p.inv_inertia, &p.r})
    out.push_back((*a)[i]);
  out.push_back(static_cast<double>(p.id[i]));
  out.push_back(p.shape[i]);
  out.push_back(p.mat[i]);
}

// Writes one packed particle into slot i.
void unpack_at(Particles& p, std::size_t i, const double* in) {
  for (auto* a : {&p.x, &p.y, &p.th, &p.vx, &p.vy, &p.w, &p.vx_prev, &p.vy_prev, &p.w_prev, &p.fx, &p.fy,
                  &p.tq, &p.m, &p.inv_m, &p.inertia, &p.inv_inertia, &p.r})
    (*a)[i] = *in++;
  p.id[i] = static_cast<std::int64_t>(in[0]);
  p.shape[i] = static_cast<std::int32_t>(in[1]);
  p.mat[i] = static_cast<std::int32_t>(in[2]);
}

// Appends `count` packed particles.
void unpack(Particles& p, const double* in, std::size_t count) {
  const std::size_t first = p.size();
  p.resize(first + count);
  for (std::size_t k = 0; k < count; ++k) unpack_at(p, first + k, in + k * kFields);
}

// Keeps the particles with keep[i], in order.
void compact(Particles& p, const std::vector<char>& keep) {
  std::vector<std::uint32_t> order;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) order.push_back(static_cast<std::uint32_t>(i));
  p.permute(order);
}

double wrapped(double x, double xmin, double period) {
  return period > 0 ? x - period * std::floor((x - xmin) / period) : x;
}

}  // namespace

// Boundaries splitting weighted points (x, w) into `size` runs of equal weight; ties in x are
// broken by id so every rank computes the same cuts from the same data.
std::vector<double> weighted_cuts(const std::vector<double>& xw_id, int size,
                                  const std::vector<double>& shares) {
  if (size <= 1) return {};
  const std::size_t n = xw_id.size() / 3;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return xw_id[3 * a] != xw_id[3 * b] ? xw_id[3 * a] < xw_id[3 * b] : xw_id[3 * a + 2] < xw_id[3 * b + 2];
  });
  double total = 0;
  for (std::size_t k = 0; k < n; ++k) total += xw_id[3 * k + 1];
  std::vector<double> cut;
  double acc = 0;
  std::size_t k = 0;
  const bool shared = shares.size() == static_cast<std::size_t>(size);
  double before = 0;  // the shares of the runs left of cut q
  for (int q = 1; q < size; ++q) {
    before += shared ? shares[q - 1] : 0.0;
    const double target = shared ? total * before : total * q / size;
    while (k + 1 < n && acc + xw_id[3 * order[k] + 1] <= target) acc += xw_id[3 * order[k++] + 1];
    const double left = n ? xw_id[3 * order[k > 0 ? k - 1 : 0]] : 0.0, right = n ? xw_id[3 * order[k]] : 0.0;
    double c = 0.5 * (left + right);
    if (!cut.empty()) c = std::max(c, cut.back());
    cut.push_back(c);
  }
  return cut;
}

bool World::any_rank(bool mine) const {
  if (!domain_) return mine;
  const auto t0 = std::chrono::steady_clock::now();
  const bool any = parallel::any_all(mine);
  load_.seconds_communication += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return any;
}

// Every rank built the whole scene identically; each keeps the slab holding an equal share of it.
void World::distribute_initial() {
  Domain d;
  d.rank = parallel::rank();
  d.size = parallel::size();
  d.periodic = period_ > 0;
  d.xmin = xmin_;
  d.period = period_;
  double rmax = 0;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    if (p_.shape[i] >= 0)
      throw std::runtime_error("a distributed native world holds discs only (this scene has polygons)");
    rmax = std::max(rmax, p_.r[i]);
  }
  d.halo = 2 * rmax + skin_;
  d.py = decomposition_.ranks_y;
  if (d.py < 1 || d.size % d.py != 0)
    throw std::runtime_error(fmt::format("{} ranks cannot form a grid with {} rows", d.size, d.py));
  d.px = d.size / d.py;
  std::vector<double> points;
  for (std::size_t i = 0; i < p_.size(); ++i)
    points.insert(points.end(),
                  {wrapped(p_.x[i], xmin_, period_), p_.y[i], 1.0, static_cast<double>(p_.id[i])});
  d.cut_evenly(points);
  d.next_balance_step = decomposition_.balance_every;
  std::vector<char> keep(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i)
    keep[i] = d.owner(wrapped(p_.x[i], xmin_, period_), p_.y[i]) == d.rank;
  compact(p_, keep);
  n_own_ = p_.size();
  domain_ = std::move(d);
}

// Owned particles that left the slab go to their new owner with every committed shear spring they
// take part in (the new owner needs them; the old one keeps its copy for pairs it still computes).
void World::migrate(std::vector<SavedShear>& saved) {
  const auto t0 = std::chrono::steady_clock::now();
  Domain& d = *domain_;
  std::vector<std::vector<double>> send(d.size);
  std::vector<char> keep(n_own_, 1);
  std::unordered_map<std::int64_t, int> leaving;
  for (std::size_t i = 0; i < n_own_; ++i) {
    const int q = d.owner(p_.x[i], p_.y[i]);
    if (q == d.rank) continue;
    keep[i] = 0;
    leaving[p_.id[i]] = q;
  }
  std::vector<std::vector<double>> particles(d.size), history(d.size);
  for (std::size_t i = 0; i < n_own_; ++i)
    if (!keep[i]) pack(p_, i, particles[leaving[p_.id[i]]]);
  for (const SavedShear& s : saved)
    for (std::int64_t id : {s.a, s.b})
      if (auto it = leaving.find(id); it != leaving.end())
        history[it->second].insert(history[it->second].end(),
                                   {static_cast<double>(s.a), static_cast<double>(s.b), s.xi});
  for (int q = 0; q < d.size; ++q) {
    send[q].push_back(static_cast<double>(particles[q].size() / kFields));
    send[q].insert(send[q].end(), particles[q].begin(), particles[q].end());
    send[q].insert(send[q].end(), history[q].begin(), history[q].end());
  }
  const std::vector<std::vector<double>> recv = parallel::all_to_all(send);
  compact(p_, keep);
  for (int q = 0; q < d.size; ++q) {
    if (q == d.rank || recv[q].empty()) continue;
    const std::size_t count = static_cast<std::size_t>(recv[q][0]);
    const double* in = recv[q].data() + 1;
    unpack(p_, in, count);
    in += count * kFields;
    for (const double* end = recv[q].data() + recv[q].size(); in + 2 < end; in += 3) {
      const auto a = static_cast<std::int64_t>(in[0]), b = static_cast<std::int64_t>(in[1]);
      saved.push_back({shear_key(a, b), a, b, in[2]});
    }
  }
  n_own_ = p_.size();
  load_.seconds_communication += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Copies of the owned particles within `halo` of another rank's slab go to that rank, which appends
// them after its own; the lists are kept for the per-step updates until the next rebuild.
void World::receive_ghosts() {
  const auto t0 = std::chrono::steady_clock::now();
  Domain& d = *domain_;
  d.send_index.assign(d.size, {});
  const double halo = d.halo + extra_reach_;
  for (std::size_t i = 0; i < n_own_; ++i) {
    const double x = p_.x[i], y = p_.y[i];
    if (d.distance_to_own_edge(x, y) > halo) continue;
    for (int q = 0; q < d.size; ++q)
      if (q != d.rank && d.distance_to_region(x, y, q) < halo)
        d.send_index[q].push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<std::vector<double>> send(d.size);
  for (int q = 0; q < d.size; ++q)
    for (std::uint32_t i : d.send_index[q]) pack(p_, i, send[q]);
  const std::vector<std::vector<double>> recv = parallel::all_to_all(send);
  d.to.clear(), d.from.clear(), d.recv_count.clear();
  std::vector<std::vector<std::uint32_t>> lists;
  for (int q = 0; q < d.size; ++q) {
    if (q == d.rank) continue;
    if (!d.send_index[q].empty()) {
      d.to.push_back(q);
      lists.push_back(d.send_index[q]);
    }
    if (recv[q].empty()) continue;
    d.from.push_back(q);
    d.recv_count.push_back(recv[q].size() / kFields);
    unpack(p_, recv[q].data(), recv[q].size() / kFields);
  }
  d.send_index = std::move(lists);
  d.send_buf.assign(d.to.size(), {});
  d.recv_buf.assign(d.from.size(), {});
  for (std::size_t k = 0; k < d.from.size(); ++k) d.recv_buf[k].resize(5 * d.recv_count[k]);
  ghosts_fresh_ = true;
  load_.seconds_communication += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The ghosts' positions and velocities, from their owners (what the force kernels read).
void World::update_ghosts() {
  if (!domain_) return;
  const auto t0 = std::chrono::steady_clock::now();
  Domain& d = *domain_;
  for (std::size_t k = 0; k < d.to.size(); ++k) {
    std::vector<double>& b = d.send_buf[k];
    b.clear();
    for (std::uint32_t i : d.send_index[k])
      b.insert(b.end(), {p_.x[i], p_.y[i], p_.vx[i], p_.vy[i], p_.w[i]});
  }
  parallel::exchange(d.to, d.send_buf, d.from, d.recv_buf);
  std::size_t g = n_own_;
  for (const std::vector<double>& b : d.recv_buf)
    for (std::size_t k = 0; k < b.size(); k += 5, ++g) {
      p_.x[g] = b[k], p_.y[g] = b[k + 1], p_.vx[g] = b[k + 2], p_.vy[g] = b[k + 3], p_.w[g] = b[k + 4];
    }
  ghosts_fresh_ = true;
  load_.seconds_communication += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Re-splits the slabs so that each holds an equal share of the load. A particle's load is one (its
// integration) plus its listed pairs (force work), measured on the lists in hand.
void World::balance_regions() {
  Domain& d = *domain_;
  std::vector<double> mine;
  for (std::size_t i = 0; i < n_own_; ++i) {
    const double pairs =
        discs_.inc_offset.size() > i + 1 ? discs_.inc_offset[i + 1] - discs_.inc_offset[i] : 0;
    mine.insert(mine.end(), {p_.x[i], p_.y[i], 1.0 + pairs, static_cast<double>(p_.id[i])});
  }
  d.cut_evenly(parallel::gather_all(mine));
  d.next_balance_step = diag_.steps + decomposition_.balance_every;
  ++load_.balances;
}

Particles World::gather_particles() const {
  Particles all;
  if (domain_) {
    std::vector<double> mine;
    mine.reserve(n_own_ * kFields);
    for (std::size_t i = 0; i < n_own_; ++i) pack(p_, i, mine);
    const std::vector<double> gathered = parallel::gather_to_root(mine);
    unpack(all, gathered.data(), gathered.size() / kFields);
  } else {
    all = p_;
  }
  std::vector<std::uint32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return all.id[a] < all.id[b]; });
  all.permute(order);
  return all;
}

}  // namespace grainlab::dem
