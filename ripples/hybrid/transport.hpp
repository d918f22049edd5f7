#pragma once
// One step of the 3-D hybrid model's transport (Huo et al. 2021, section 2.6, steps ii-v and vii):
// airborne grains tracked one by one (drag of the huo2021 law, buoyant gravity, Heun steps with the wind
// frozen), mid-air collisions, the Lammel splash where a grain reaches the bed (in the frame of the bed
// triangle beneath it, with the wind-loosened E_eff if asked), and the steady wind column updated from
// the grains' drag every wind_interval. The bed is either fixed and flat (the flux runs) or a height field
// that the grains that settle and leave change (the ripple runs).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "airborne.hpp"
#include "bed_relief.hpp"
#include "h5_output.hpp"
#include "height_field.hpp"
#include "lammel_splash.hpp"
#include "recorded_splash.hpp"
#include "rng.hpp"
#include "wind_column.hpp"

namespace grainlab::ripples::hybrid {

struct TransportOptions {
  double diameter = 0.025;                         // cm
  double grain_density = 2.65;                     // g/cm^3
  double fluid_density = 0.00123;                  // g/cm^3
  double viscosity = 0.146;                        // cm^2/s
  double g = 981;                                  // cm/s^2
  double u_star = 40;                              // cm/s
  double length = 400, width = 10, height = 1200;  // domain in diameters (x streamwise, y, wind column)
  int triggers = 40;                               // grains thrown at the start (random places, 20 d/s up)
  double dt_max = 0.02;                            // in sqrt(d / g); also |v| dt < travel d
  // The most a grain moves in a step, d. The paper's bound, 0.2, keeps mid-air collisions found by
  // overlaps at the steps' ends. With `swept`, pairs are found by their paths over the step and impacts
  // are traced back to where the grain crossed the bed, so a grain may move further (1.5: the step of
  // dt_max for grains up to 75 sqrt(g d), about seven times fewer steps per t*; docs/hybrid.md). Swept
  // steps are also kept short enough that no two grains close on each other by more than (4/3) travel
  // downwind or (2/3) travel across it, the collision columns' margins (grains differ in speed across the
  // wind about half as much as along it).
  double travel = 0.2;
  bool swept = false;
  // With `swept`: every step is dt_max long, and a grain that would move more than `travel` in it takes
  // as many substeps as keep it within `travel` each. Without, the fastest grain sets everyone's step: on
  // the paper's domain one grain in a hundred flies faster than 75 sqrt(g d), and a rare ejectum from the
  // splash's energy tail at up to ~300, which halves the step of 30,000 grains for the hundreds of t* it
  // flies (docs/hybrid.md, "A step for the fast grains"). Mid-air pairs with a grain whose velocity lies
  // outside the range the collision columns allow at dt_max are found by a pass of their own.
  bool fast_substeps = false;
  double wind_interval = 1;  // t* between wind updates
  double wind_memory = 20;   // t*: the grains' drag is a running mean over this
  bool collisions = true;
  // Whether the grains one splash sends up (its rebound and ejecta, launched from within a diameter of
  // each other) may collide with each other in the air. The splash function's velocities are already
  // the outcome of their contacts in the bed, so by default they do not: colliding them again took most
  // of the rebound's speed in five of six mid-air collisions (docs/hybrid.md, "Collisions within a
  // splash").
  bool collide_within_splash = false;
  double collision_restitution = 0.9, collision_friction = 0.4;
  std::string splash = "paper2021";  // LammelParameters::named; with `recorded`, the file's name
  // Recorded impacts (a grainlab-splash/1 file's cells) in place of the Lammel splash, when set.
  std::shared_ptr<const RecordedSplash> recorded;
  // Eq. 19: bed grains loosened by the wind's stress at the bed need E_eff = E_d2 (1 - tau_fw / tau_ft),
  // tau_ft of Shao & Lu (2000); floored at loosened_floor E_d2 (early on the stress passes the threshold).
  bool wind_loosened = false;
  // Ejecta leave along the local bed's normal (the spec's reading of the paper), or straight up.
  bool ejecta_vertical = false;
  // The splash (impact angle, rebound and ejecta) in the frame of the bed triangle hit (the paper's
  // section 2.2), or of the level bed, as if the bed were flat where the grain lands.
  bool splash_level = false;
  double loosened_floor = 0.1;
  // The wind column's height is measured from the mean bed level (the paper's horizontally homogeneous
  // column), or from the bed right beneath each grain, so that the near-bed wind follows the topography
  // (crests do not reach into faster wind than troughs).
  bool wind_follows_bed = false;
  // With wind_follows_bed: the column stands on the bed's relief (its height less the mean level) as it
  // fades with the height s above the bed in potential flow, each Fourier mode as exp(-|k| s)
  // (bed_relief.hpp), instead of on the whole relief at every height.
  bool wind_relief_fades = false;
  // A rebound or ejectum is dead (it settles) when its centre cannot rise this many diameters above where
  // it leaves: the paper's "particles which cannot jump higher than 1d" (eq. 31's flux depends on it).
  double dead_rise = 1;
  // A bed of several grain sizes (the paper's section 3.2.2): each class's diameter in units of
  // `diameter` (which stays the unit of t*, Q* and S) and its fraction of the bed by volume. Empty: one
  // size. The Lammel splash then takes the impactor's size as d1 and the size of the bed grain it meets
  // (drawn from the surface layer where it lands) as d2; the ejecta are of that bed grain's size.
  std::vector<double> sizes, fractions;
  // On a bed of several sizes, the ejecta's sizes: "local" (default), each of the size drawn from the
  // surface where it sits, leaving only if its energy (drawn from the law for d2) beats its own m g d, so
  // that fines go and coarse grains stay; or "struck", all of the size of the bed grain the impact met
  // (d2). Only "local" gives the paper's coarse crests with the geometric rolling rule (docs/hybrid.md).
  std::string ejecta_size = "local";
  std::uint64_t seed = 2021;
  // Spread the domain over the MPI ranks in x (each rank flies the grains over its share; the bed, the
  // splash and the wind are the same on every rank). Off: every rank runs the whole model (the validation
  // suites give ranks whole runs). Either way the results do not depend on the rank count, bit for bit.
  bool distributed = false;
};

// A checkpoint's table by name with rows `columns` wide; throws std::invalid_argument otherwise.
const SampleTable& checkpoint_table(const std::map<std::string, SampleTable>& tables, const std::string& name,
                                    std::size_t columns);
// The same for a table whose columns the caller judges by name: its rows as wide as its own columns.
const SampleTable& checkpoint_table(const std::map<std::string, SampleTable>& tables,
                                    const std::string& name);

// Values on a grid nx wide (x fastest) as a table with one row per line of nx (columns x0, x1, ...), and
// back: a checkpoint holds beds and profiles without a row per value.
SampleTable grid_table(std::string name, std::string description, const std::vector<double>& values,
                       std::size_t nx);
std::vector<double> grid_values(const SampleTable& t);

// Throws std::invalid_argument for options that cannot run.
void check_transport_options(const TransportOptions& o);

// How long before now a grain at p moving straight at v had its bottom (radius r) on the surface
// height(x, y): the first point of its path back from p that touches the surface, searched to `span`
// seconds back (gravity bends a step's path by only g dt^2 ~ 4e-4 d). 0 when it is not descending or
// was below the surface `span` ago too. Swept steps trace impacts back with it.
// (A template, so that each impact's ~40 height lookups inline.)
template <class Height>
double time_since_crossing(const std::array<double, 3>& p, const std::array<double, 3>& v, double r,
                           double span, const Height& height) {
  auto above = [&](double back) {  // the bottom's height over the surface, `back` seconds ago
    return p[2] - v[2] * back - r - height(p[0] - v[0] * back, p[1] - v[1] * back);
  };
  if (!(v[2] < 0) || above(span) <= 0) return 0;
  double lo = 0, hi = span;  // below at lo, above at hi
  for (int k = 0; k < 50 && hi - lo > 1e-12 * span; ++k)
    (above(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
  return hi;
}

// Impacts counted since the caller last cleared them.
struct ImpactTally {
  double impacts = 0, speed_sum = 0, angle_sum = 0;  // cm/s, rad
  std::uint64_t deaths = 0, ejecta = 0;
  // Momentum per unit grain mass the bed takes (cm/s, summed): downwind, v_x in - v_x out, and downward,
  // v_z out - v_z in, over every grain that reaches it and every rebound and ejectum that leaves it. Their
  // ratio is the bed friction coefficient mu_b of eq. 31 (Pahtz & Duran 2020). Flux runs only: a
  // checkpoint does not keep them.
  double bed_px = 0, bed_pz = 0;
};

// One impact as the splash met it, for a log (nothing in the model reads it back): where the grain met the
// bed, its velocity, and the normal of the bed triangle there (the grain-scale facet, whichever frame the
// splash is taken in).
struct ImpactRecord {
  double t;           // s
  double x, y;        // cm
  double vx, vy, vz;  // cm/s
  double nx, ny, nz;
  int kind;  // size class
};

// The x columns of the collision grid are grouped into this many blocks (fewer on short domains: a block
// is at least two columns wide); a distributed run gives each rank whole blocks, so it can use at most
// this many ranks. A constant, not the rank count: it fixes the order of mid-air collisions.
inline constexpr long kCollisionBlocks = 64;

// The most MPI ranks a distributed run of these options can use (one block each).
long max_ranks(const TransportOptions& o);

class Transport {
 public:
  // `bed` null: a fixed flat bed at z = 0 with unlimited sand. Otherwise the bed must cover the domain.
  Transport(const TransportOptions& o, HeightField* bed);
  void step();
  double time() const { return t_; }                  // s
  double time_unit() const { return t_unit_; }        // sqrt(d / g^), s
  double mass_flux() const;                           // g/(cm s), now; collective on a distributed run
  double flux_unit() const;                           // rho_p d sqrt(s g^ d): Q* = Q / flux_unit
  std::size_t airborne() const { return airborne_; }  // on every rank
  std::uint64_t total_collisions() const;             // every rank's; collective on a distributed run
  std::size_t size_classes() const { return classes_.size(); }
  double class_diameter(int k) const { return classes_[static_cast<std::size_t>(k)].d; }  // cm
  const Grains& grains() const { return grains_; }  // this rank's (all of them unless distributed)
  const WindColumn& wind() const { return wind_; }
  double loosening() const { return loosening_; }  // E_eff / E_d2 now
  double shields() const;
  double galileo() const;
  double density_ratio() const { return s_; }
  ImpactTally tally;  // every impact's, on every rank
  // When set, every impact is appended here, on every rank alike (every rank does every splash).
  std::vector<ImpactRecord>* impact_log = nullptr;
  std::uint64_t grain_steps = 0, steps = 0;
  std::uint64_t collisions = 0;  // this rank's: total_collisions() sums them
  // fast_substeps: the pairs the fast pass collided (every rank does it whole: the same on each); also
  // counted in collisions, on the first rank.
  std::uint64_t fast_collisions = 0;
  // Everything a continued run needs, as named tables (prefix + "grains", "ids", "wind", "clock"); restore
  // takes them back (throws std::invalid_argument when one is missing or the wrong shape). Both are
  // collective on a distributed run, and a run continued on any rank count goes on bit for bit. A
  // checkpoint without ids (written before they existed) numbers its grains in row order.
  std::vector<SampleTable> save(const std::string& prefix) const;
  void restore(const std::map<std::string, SampleTable>& tables, const std::string& prefix);

 private:
  void move_grains(double dt);
  template <bool kFollowsBed, bool kMixed>
  void move_grains_as(double dt);
  void collide();
  void collide_rank_edges();
  void collide_fast();
  // fast_substeps: whether a velocity lies outside the range the collision columns allow at the step.
  bool fast(double vx, double vy) const {
    return vx < box_[0] || vx > box_[1] || vy < box_[2] || vy > box_[3];
  }
  void migrate();
  void finish_step();
  // A grain at or below the bed: a copy of its state, and where it sits here (-1: on another rank).
  struct Hit {
    std::uint64_t id;
    double x, y, z, vx, vy, vz;
    int kind;
    long local;
  };
  std::vector<Hit> hits();  // every rank's, in ascending id
  void impacts();
  void splash(Hit& h);
  void rebound(const Hit& h, double x, double y, double z, double vx, double vy, double vz);
  void crossing(const Hit& h, double r, double& x, double& y) const;
  // Swept steps: widens the range of the grains' horizontal velocities the next step starts from.
  void spread_by(double vx, double vy) {
    spread_[0] = std::min(spread_[0], vx), spread_[1] = std::max(spread_[1], vx);
    spread_[2] = std::min(spread_[2], vy), spread_[3] = std::max(spread_[3], vy);
  }
  double swept_step(double dt) const;
  void settle(const Hit& h);
  void launch(double x, double y, double bed_height, double vx, double vy, double vz, int kind);
  int bed_kind(double x, double y);  // the size class of the bed grain an impact at (x, y) meets
  void recorded_splash(Hit& h, double px, double py, const BedPoint& b, const std::array<double, 3>& t,
                       double speed, double theta);
  bool mine(double x) const { return owner_[static_cast<std::size_t>(grid_.column_x(x))] == rank_; }
  std::vector<std::int64_t> summed(const std::vector<std::int64_t>& v) const;  // over the ranks, exactly
  void update_wind();
  double tau_threshold() const;  // Shao & Lu (2000), tau_ft / rho_f

  // What the loops need of each size class (one class in a run of one size).
  struct SizeClass {
    double d, m, volume, drag_a, drag_b, e_d2, rise2;
  };
  TransportOptions o_;
  HeightField* bed_;
  LammelParameters splash_;
  std::vector<SizeClass> classes_;
  std::vector<LammelCoefficients> coefficients_;  // impactor class k1, bed class k2: [k1 * classes + k2]
  bool mixed_ = false, local_ejecta_ = false;
  double d_, s_, g_hat_, t_unit_, length_, width_, area_, m_, volume_;
  double drag_a_, drag_b_, base_ = 0, loosening_ = 1;
  std::optional<BedRelief> relief_;  // wind_relief_fades
  std::vector<double> relief_bed_;   // the bed it was last taken from, and its mean (a checkpoint keeps them)
  double relief_mean_ = 0;
  int winds_since_relief_ = 0;
  static constexpr int kReliefEvery = 10;  // wind updates
  // fast_substeps: the velocities (cm/s, x then y) whose pairs the collision columns hold at dt_max.
  std::array<double, 4> box_{-1e300, 1e300, -1e300, 1e300};
  std::vector<std::uint8_t> marked_;      // per column: one a fast grain may have met a grain in (kept clear)
  std::vector<std::uint32_t> near_head_;  // per column: a fast-pass partner in it, chained (kept clear)
  double r_max_;  // the largest grain's radius, cm: no grain whose centre is higher above the top touches
  double rise2_;  // squared launch speed that lifts a centre dead_rise diameters: below it, a grain settles
  WindColumn wind_;
  std::vector<double> drag_mean_, volume_mean_;
  // The drag and volume since the last wind update, in fixed point (units of 1 / drag_scale_ and
  // 1 / volume_scale_): integer sums come out the same whatever order the grains are added in, so the
  // wind does not depend on how the grains are spread over ranks.
  std::vector<std::int64_t> drag_now_, volume_now_;
  double drag_scale_ = 1, volume_scale_ = 1, flux_scale_ = 1;
  // The decomposition: this rank, the rank count, the owner of each x column of the collision grid, and
  // this rank's first and last x column.
  int rank_ = 0, ranks_ = 1;
  std::vector<int> owner_;
  long first_x_ = 0, last_x_ = 0;
  std::uint64_t next_id_ = 0, airborne_ = 0, launched_ = 0, settled_ = 0;  // (the last two: this step's)
  std::uint64_t splash_now_ = kNoSplash;  // the number of the splash being done (Grains::splash)
  std::vector<char> dead_;
  Rng rng_;
  Grains grains_;
  CollisionGrid grid_;
  CollisionLaw law_;
  double t_ = 0, next_wind_ = 0, since_wind_ = 0, v2_next_ = 0, v2_launch_ = 0, dt_ = 0;
  // Swept steps: the least and most v_x and v_y of the grains as the next step starts (cm/s), and how far
  // two grains may close on each other along x and y in a step (cm): the collision columns' margins.
  std::array<double, 4> spread_{1e300, -1e300, 1e300, -1e300};
  double reach_x_ = 1e300, reach_y_ = 1e300;
};

}  // namespace grainlab::ripples::hybrid
