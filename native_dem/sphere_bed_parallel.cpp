// A sphere bed spread over MPI ranks: the initial split into regions, and at each neighbour-list rebuild
// the re-cut that evens out the load, migration of spheres (with their springs) between ranks, ghost
// copies of the neighbours' spheres, then every step the ghosts' positions and velocities. docs/parallel.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <stdexcept>

#include "parallel.hpp"
#include "sphere_bed.hpp"

namespace grainlab::dem {

namespace {
// A sphere's whole state (migration), and what a ghost needs (id, x, v, w, m, r, material, inverse
// moment of inertia). Ids and materials are exact in a double.
constexpr std::size_t kWhole = 24, kGhost = 14, kUpdate = 9, kSpring = 5;

double wrapped(double x, const std::optional<std::pair<double, double>>& period) {
  if (!period) return x;
  const double L = period->second - period->first;
  return x - L * std::floor((x - period->first) / L);
}
}  // namespace

bool SphereBed::any_rank(bool mine) const {
  return domain_ ? parallel::any_all(mine) : mine;
}

void SphereBed::distribute(const Decomposition& decomposition) {
  if (!in_place_.empty()) throw std::logic_error("a bed with spheres held in place runs on one rank");
  decomposition_ = decomposition;
  Domain d;
  d.rank = parallel::rank();
  d.size = parallel::size();
  d.periodic = s_.periodic_x.has_value();
  if (d.periodic) d.xmin = s_.periodic_x->first, d.period = s_.periodic_x->second - s_.periodic_x->first;
  d.halo = 2 * max_radius_ + skin_;
  d.py = decomposition.ranks_y;
  if (d.py < 1 || d.size % d.py != 0)
    throw std::runtime_error(fmt::format("{} ranks cannot form a grid with {} rows", d.size, d.py));
  if (d.py > 1 && s_.periodic_y)
    throw std::runtime_error("a bed periodic in y is split into slabs along x only (ranks_y = 1)");
  d.px = d.size / d.py;
  std::vector<double> points;
  for (std::size_t i = 0; i < x_.size(); ++i)
    points.insert(points.end(),
                  {wrapped(x_[i].x(), s_.periodic_x), x_[i].y(), 1.0, static_cast<double>(id_[i])});
  d.cut_evenly(points);
  d.next_balance_step = decomposition.balance_every;
  next_probe_ = decomposition.probe_every, recut_now_ = false;
  sweep_cost_.clear(), asked_.clear();
  std::vector<std::uint32_t> keep;
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (d.owner(wrapped(x_[i].x(), s_.periodic_x), x_[i].y()) == d.rank)
      keep.push_back(static_cast<std::uint32_t>(i));
  const std::size_t np = s_.planes.size();
  std::vector<Vec3> planes(keep.size() * np);
  for (std::size_t k = 0; k < keep.size(); ++k)
    for (std::size_t p = 0; p < np; ++p) planes[k * np + p] = plane_xi_[keep[k] * np + p];
  auto pick = [&](auto& a) {
    std::remove_reference_t<decltype(a)> out;
    out.reserve(keep.size());
    for (std::uint32_t i : keep) out.push_back(a[i]);
    a = std::move(out);
  };
  pick(id_), pick(x_), pick(v_), pick(w_), pick(f_), pick(tq_), pick(q_), pick(m_), pick(inv_m_),
      pick(inv_i_), pick(r_), pick(mat_);
  plane_xi_ = std::move(planes);
  ghost_.assign(x_.size(), 0);
  spring_at_.clear(), springs_.clear(), springs_used_ = 0;
  cells_ = SphereCells();
  if (s_.periodic_x) cells_.set_period(0, s_.periodic_x->first, s_.periodic_x->second);
  if (s_.periodic_y) cells_.set_period(1, s_.periodic_y->first, s_.periodic_y->second);
  moved_ = true, prediction_ = Prediction::unknown;
  domain_ = std::move(d);
}

// All slots in id order again (owned spheres and ghosts interleaved): the order every sum follows.
void SphereBed::sort_slots() {
  std::vector<std::uint32_t> order(x_.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return id_[a] < id_[b]; });
  auto permute = [&](auto& a) {
    std::remove_reference_t<decltype(a)> out;
    out.reserve(order.size());
    for (std::uint32_t i : order) out.push_back(a[i]);
    a = std::move(out);
  };
  permute(id_), permute(x_), permute(v_), permute(w_), permute(f_), permute(tq_), permute(q_), permute(m_),
      permute(inv_m_), permute(inv_i_), permute(r_), permute(mat_), permute(ghost_);
}

void SphereBed::exchange_spheres(std::vector<SphereSpring>& held) {
  Domain& d = *domain_;
  // Ghosts go: they come again, fresh, below.
  {
    std::vector<std::uint32_t> own;
    for (std::size_t i = 0; i < x_.size(); ++i)
      if (!ghost_[i]) own.push_back(static_cast<std::uint32_t>(i));
    std::vector<double> load;  // for a re-cut: (x, y, 1 + listed pairs, id) per sphere of this rank
    const bool recut = recut_now_ || (decomposition_.balance_every > 0 && steps_ >= d.next_balance_step);
    if (recut)
      for (std::uint32_t i : own) {
        const double pairs =
            cells_.builds() && cells_.entries() ? double(cells_.end(i) - cells_.begin(i)) : 0.0;
        load.insert(load.end(), {x_[i].x(), x_[i].y(), 1.0 + pairs, static_cast<double>(id_[i])});
      }
    if (recut) {
      d.cut_evenly(parallel::gather_all(load));
      d.next_balance_step = steps_ + decomposition_.balance_every;
      recuts_ += recut_now_ ? 1 : 0;
      recut_now_ = false;
    }
    auto pick = [&](auto& a) {
      std::remove_reference_t<decltype(a)> out;
      out.reserve(own.size());
      for (std::uint32_t i : own) out.push_back(a[i]);
      a = std::move(out);
    };
    pick(id_), pick(x_), pick(v_), pick(w_), pick(f_), pick(tq_), pick(q_), pick(m_), pick(inv_m_),
        pick(inv_i_), pick(r_), pick(mat_);
    ghost_.assign(x_.size(), 0);
  }
  // Spheres whose centre left the region go to their new owner with every spring they are part of.
  std::vector<std::vector<double>> send(d.size);
  std::vector<int> owner(x_.size());
  std::vector<std::uint32_t> stay;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    owner[i] = d.owner(x_[i].x(), x_[i].y());
    if (owner[i] == d.rank) {
      stay.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    std::vector<double>& out = send[owner[i]];
    out.insert(out.end(), {static_cast<double>(id_[i]),
                           x_[i].x(),
                           x_[i].y(),
                           x_[i].z(),
                           v_[i].x(),
                           v_[i].y(),
                           v_[i].z(),
                           w_[i].x(),
                           w_[i].y(),
                           w_[i].z(),
                           f_[i].x(),
                           f_[i].y(),
                           f_[i].z(),
                           tq_[i].x(),
                           tq_[i].y(),
                           tq_[i].z(),
                           q_[i].w(),
                           q_[i].x(),
                           q_[i].y(),
                           q_[i].z(),
                           m_[i],
                           inv_i_[i],
                           r_[i],
                           static_cast<double>(mat_[i])});
  }
  std::vector<std::vector<double>> springs(d.size);
  for (const SphereSpring& sp : held)
    for (std::int64_t id : {sp.a, sp.b}) {
      if (id < 0) continue;
      const auto it = std::lower_bound(id_.begin(), id_.end(), id);
      if (it == id_.end() || *it != id) continue;
      const int q = owner[static_cast<std::size_t>(it - id_.begin())];
      if (q != d.rank)
        springs[q].insert(springs[q].end(), {double(sp.a), double(sp.b), sp.xi.x(), sp.xi.y(), sp.xi.z()});
    }
  for (int q = 0; q < d.size; ++q) {
    std::vector<double> msg{static_cast<double>(send[q].size() / kWhole)};
    msg.insert(msg.end(), send[q].begin(), send[q].end());
    msg.insert(msg.end(), springs[q].begin(), springs[q].end());
    send[q] = std::move(msg);
  }
  const std::vector<std::vector<double>> arrived = parallel::all_to_all(send);
  {
    auto pick = [&](auto& a) {
      std::remove_reference_t<decltype(a)> out;
      out.reserve(stay.size());
      for (std::uint32_t i : stay) out.push_back(a[i]);
      a = std::move(out);
    };
    pick(id_), pick(x_), pick(v_), pick(w_), pick(f_), pick(tq_), pick(q_), pick(m_), pick(inv_m_),
        pick(inv_i_), pick(r_), pick(mat_);
  }
  for (int q = 0; q < d.size; ++q) {
    if (q == d.rank || arrived[q].empty()) continue;
    const auto count = static_cast<std::size_t>(arrived[q][0]);
    const double* in = arrived[q].data() + 1;
    for (std::size_t k = 0; k < count; ++k, in += kWhole) {
      id_.push_back(static_cast<std::int64_t>(in[0]));
      x_.emplace_back(in[1], in[2], in[3]), v_.emplace_back(in[4], in[5], in[6]),
          w_.emplace_back(in[7], in[8], in[9]);
      f_.emplace_back(in[10], in[11], in[12]), tq_.emplace_back(in[13], in[14], in[15]);
      q_.emplace_back(in[16], in[17], in[18], in[19]);
      m_.push_back(in[20]), inv_m_.push_back(1 / in[20]), inv_i_.push_back(in[21]), r_.push_back(in[22]);
      note_kind(m_.size() - 1);
      mat_.push_back(static_cast<std::int32_t>(in[23]));
    }
    for (const double* end = arrived[q].data() + arrived[q].size(); in + kSpring <= end; in += kSpring)
      held.push_back(
          {static_cast<std::int64_t>(in[0]), static_cast<std::int64_t>(in[1]), Vec3(in[2], in[3], in[4])});
  }
  ghost_.assign(x_.size(), 0);
  // Copies of this rank's spheres within the halo of another region go to that rank.
  std::vector<std::vector<std::int64_t>> sent_ids(d.size);
  std::vector<std::vector<double>> ghosts(d.size);
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const double x = x_[i].x(), y = x_[i].y();
    if (d.distance_to_own_edge(x, y) > d.halo) continue;
    for (int q = 0; q < d.size; ++q)
      if (q != d.rank && d.distance_to_region(x, y, q) < d.halo) {
        sent_ids[q].push_back(id_[i]);
        ghosts[q].insert(ghosts[q].end(), {static_cast<double>(id_[i]), x, y, x_[i].z(), v_[i].x(), v_[i].y(),
                                           v_[i].z(), w_[i].x(), w_[i].y(), w_[i].z(), m_[i], r_[i],
                                           static_cast<double>(mat_[i]), inv_i_[i]});
      }
  }
  const std::vector<std::vector<double>> received = parallel::all_to_all(ghosts);
  std::vector<std::vector<std::int64_t>> received_ids(d.size);
  for (int q = 0; q < d.size; ++q)
    for (std::size_t k = 0; k + kGhost <= received[q].size(); k += kGhost) {
      const double* in = received[q].data() + k;
      received_ids[q].push_back(static_cast<std::int64_t>(in[0]));
      id_.push_back(static_cast<std::int64_t>(in[0]));
      x_.emplace_back(in[1], in[2], in[3]), v_.emplace_back(in[4], in[5], in[6]),
          w_.emplace_back(in[7], in[8], in[9]);
      f_.emplace_back(Vec3::Zero()), tq_.emplace_back(Vec3::Zero()), q_.emplace_back(Quat::Identity());
      m_.push_back(in[10]), inv_m_.push_back(1 / in[10]), r_.push_back(in[11]);
      mat_.push_back(static_cast<std::int32_t>(in[12])), inv_i_.push_back(in[13]);
      note_kind(m_.size() - 1);
      ghost_.push_back(1);
    }
  sort_slots();
  // The plan for the per-step updates, by slot.
  to_.clear(), from_.clear(), send_slots_.clear(), recv_slots_.clear();
  for (int q = 0; q < d.size; ++q) {
    if (!sent_ids[q].empty()) {
      to_.push_back(q);
      auto& slots = send_slots_.emplace_back();
      for (std::int64_t id : sent_ids[q]) slots.push_back(static_cast<std::uint32_t>(slot_of(id)));
    }
    if (!received_ids[q].empty()) {
      from_.push_back(q);
      auto& slots = recv_slots_.emplace_back();
      for (std::int64_t id : received_ids[q]) slots.push_back(static_cast<std::uint32_t>(slot_of(id)));
    }
  }
  not_swept_ = ghost_;
  sent_once_.clear();
  for (const auto& slots : send_slots_)
    for (std::uint32_t i : slots) not_swept_[i] = 1;
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (not_swept_[i] && !ghost_[i]) sent_once_.push_back(static_cast<std::uint32_t>(i));
  // Decided alike on every rank: a rank that thought the flag rides while another did not would wait
  // for a message that never comes.
  const auto others = static_cast<std::size_t>(d.size - 1);
  flag_rides_ = !parallel::any_all(to_.size() != others || from_.size() != others);
  send_buf_.assign(to_.size(), {});
  for (std::size_t k = 0; k < to_.size(); ++k)
    send_buf_[k].resize(kUpdate * send_slots_[k].size() + (flag_rides_ ? 1 : 0));
  recv_buf_.assign(from_.size(), {});
  for (std::size_t k = 0; k < from_.size(); ++k)
    recv_buf_[k].resize(kUpdate * recv_slots_[k].size() + (flag_rides_ ? 1 : 0));
}

namespace {
// Test hook: GRAINLAB_RANK_SPEEDS="1,3" makes the ranks report these speeds instead of measuring them,
// so a re-cut can be forced at a known step (tests/CMakeLists.txt). Empty when unset or malformed.
std::vector<double> rank_speeds_from_environment(int ranks) {
  const char* text = std::getenv("GRAINLAB_RANK_SPEEDS");
  std::vector<double> speeds;
  if (!text) return speeds;
  for (const char* p = text; *p;) {
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !(v > 0)) return {};
    speeds.push_back(v);
    p = *end == ',' ? end + 1 : end;
    if (*end && *end != ',') return {};
  }
  return speeds.size() == static_cast<std::size_t>(ranks) ? speeds : std::vector<double>{};
}

// Each column's (or row's) share of the speeds: rank q is column q % px, row q / px.
std::vector<double> shares_of(const std::vector<double>& speed, int n, bool columns, int px) {
  std::vector<double> share(static_cast<std::size_t>(n), 0.0);
  double total = 0;
  for (std::size_t q = 0; q < speed.size(); ++q) {
    const int at = columns ? static_cast<int>(q) % px : static_cast<int>(q) / px;
    share[static_cast<std::size_t>(at)] += speed[q], total += speed[q];
  }
  for (double& s : share) s /= total;
  return share;
}

// The largest relative difference between two share vectors (an empty one is equal shares).
double share_change(const std::vector<double>& now, const std::vector<double>& next) {
  double most = 0;
  for (std::size_t k = 0; k < next.size(); ++k) {
    const double was = now.empty() ? 1.0 / double(next.size()) : now[k];
    most = std::max(most, std::abs(next[k] / was - 1));
  }
  return most;
}
}  // namespace

// A rank's speed is the load it sweeps per second: the inverse of the median over the steps since the
// last probe of a sweep's seconds per unit of load (the median, because a shared machine now and then
// takes a core away for a whole step). Cutting the regions to the speeds' shares evens out the ranks'
// times; the results do not depend on the cuts. The speeds are gathered, so every rank decides alike.
// A re-cut needs a rebuild. A periodic bed waits for its next due rebuild instead: wrapping happens at
// rebuilds, and an extra one would move the wrap off the serial run's steps (and so change the bits).
void SphereBed::probe_balance() {
  if (!balancing_by_time() || steps_ < next_probe_) return;
  next_probe_ = steps_ + decomposition_.probe_every;
  Domain& d = *domain_;
  double cost = 0;
  if (!sweep_cost_.empty()) {
    auto middle = sweep_cost_.begin() + static_cast<std::ptrdiff_t>(sweep_cost_.size() / 2);
    std::nth_element(sweep_cost_.begin(), middle, sweep_cost_.end());
    cost = *middle;
  }
  sweep_cost_.clear();
  std::vector<double> speed = rank_speeds_from_environment(d.size);
  const std::vector<double> all = parallel::gather_all({cost});
  if (speed.empty()) {
    for (double c : all) {
      if (!(c > 0)) return;  // a rank without a measured sweep (no load, or no sweep since the last probe)
      speed.push_back(1 / c);
    }
  }
  std::vector<double> xshare = shares_of(speed, d.px, true, d.px),
                      yshare = shares_of(speed, d.py, false, d.px);
  // A re-cut costs a rebuild, and one probe can be a passing disturbance: cut only when two probes in a
  // row ask for shares more than 5 % from the present ones, to their mean.
  constexpr double kWorthACut = 0.05;
  const bool wanted = std::max(share_change(d.xshare, xshare), share_change(d.yshare, yshare)) > kWorthACut;
  if (!wanted || asked_.empty()) {  // the first probe to ask: remember what it asked for
    asked_.clear();
    if (wanted) {
      asked_ = xshare;
      asked_.insert(asked_.end(), yshare.begin(), yshare.end());
    }
    return;
  }
  for (std::size_t k = 0; k < xshare.size(); ++k) xshare[k] = 0.5 * (xshare[k] + asked_[k]);
  for (std::size_t k = 0; k < yshare.size(); ++k) yshare[k] = 0.5 * (yshare[k] + asked_[xshare.size() + k]);
  asked_.clear();
  d.xshare = std::move(xshare), d.yshare = std::move(yshare);
  recut_now_ = !s_.periodic_x && !s_.periodic_y;
}

bool SphereBed::update_ghosts(bool moves_here) {
  for (std::size_t k = 0; k < to_.size(); ++k) {  // into buffers sized by the plan
    double* out = send_buf_[k].data();
    for (std::uint32_t i : send_slots_[k]) {
      const Vec3 &x = x_[i], &v = v_[i], &w = w_[i];
      out[0] = x.x(), out[1] = x.y(), out[2] = x.z(), out[3] = v.x(), out[4] = v.y(), out[5] = v.z();
      out[6] = w.x(), out[7] = w.y(), out[8] = w.z();
      out += kUpdate;
    }
    if (flag_rides_) *out = moves_here ? 1 : 0;
  }
  parallel::exchange(to_, send_buf_, from_, recv_buf_);
  bool any = moves_here;
  for (std::size_t k = 0; k < from_.size(); ++k) {
    const double* in = recv_buf_[k].data();
    for (std::uint32_t i : recv_slots_[k]) {
      x_[i] = {in[0], in[1], in[2]}, v_[i] = {in[3], in[4], in[5]}, w_[i] = {in[6], in[7], in[8]};
      in += kUpdate;
    }
    if (flag_rides_) any = any || *in != 0;
  }
  return any;
}

}  // namespace grainlab::dem
