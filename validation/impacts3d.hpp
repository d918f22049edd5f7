#pragma once
// Ch. III's impacts with spheres (issue #15): the thesis's own question of how 3-D differs from 2-D. A
// bed of spheres poured into an open box of planes, an incident sphere fired along +x at alpha_i below
// the horizontal at a random point of the bed's middle, followed for 0.07 s; the rebound and every
// ejected sphere recorded as in 2-D (impacts.hpp), with their sideways (y) velocities kept.
//
// The spheres have the thesis discs' mass (density 1.5 g/cm^3: m = 2 pi g for r = 1 cm, as 2.0 g/cm^2
// discs), so contact times and pair restitution are the 2-D ones and only the dimension differs.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ensemble.hpp"
#include "h5_output.hpp"
#include "impacts.hpp"
#include "scene.hpp"

namespace grainlab::validation {

struct Bed3dSpec {
  // "loose": poured with the bed's friction, so spheres lock where they land; "dense": poured, stiffened
  // and damped frictionless, so they slide toward close packing, then given their friction back for the
  // relaxation (the 2-D beds' two preparations, impact_bed.hpp).
  std::string preparation = "loose";
  std::uint64_t seed = 1;
  int count = 2000;                    // spheres
  double width = 67.3, depth = 20;     // the box along x (as the thesis's) and y
  double radius = 1.0, density = 1.5;  // g/cm^3: the 2-D discs' mass
  // A sieved sand: radii uniform in radius -+ radius_spread (0: every sphere of `radius`).
  double radius_spread = 0;
  // Irregular convex grains instead of spheres (the scenes' poured shape = "polyhedron": icosahedra with
  // moved vertices, stretched), each of the volume, so the mass, of the sphere of its radius. They run
  // on the general 3-D path, 200-400 times slower than spheres per grain-step.
  bool polyhedra = false;
  double k_n = 6e9, restitution = 0.85, mu = 0.5;
  double settle_time = 1.0;  // s of settling after the last sphere has fallen
  // The preparation's phases (stiffening, damping, relaxing, the test for loose spheres) last their
  // thesis-sized durations (0.005, 0.1, 0.05, 0.07 s for 1 cm grains) times this: grains of another size
  // fall and settle in times that scale as sqrt(r / g), so a sand bed takes sqrt(r / 1 cm) of them.
  double time_scale = 1;
  // The probes for spheres still moving before the build holds the bed instead (build_bed3d).
  int max_probes = 8;
  bool dense() const { return preparation == "dense"; }
  double smallest_radius() const { return radius - radius_spread; }
  double largest_radius() const { return radius + radius_spread; }
};

struct Bed3d {
  Bed3dSpec spec;
  Scene scene;  // every sphere listed as a body, at rest; the planes; the thesis's material
  // "Top of the bed": the 90th percentile of the exposed height (the highest sphere top in each
  // 2 r_b x 2 r_b column) over the middle 80 % of the box in x and y. (2-D takes the highest exposed point
  // of a line of ~30 grains; the maximum over a 3-D area of ~300 columns would be an outlier.)
  double top = 0;
  double packing_fraction = 0;  // in the interior (2 diameters from walls, floor and top)
  double build_seconds = 0;
  std::size_t removed = 0;  // spheres that would not come to rest on the surface, taken away
  std::size_t probes = 0;   // times the bed was left alone to find spheres still moving
  // Spheres still moving at the build's last look: at the last probe, deep spheres that moved over 2.5 %
  // of their radius; after holds (build_holds > 0), spheres over the at-rest limits. 0: at rest.
  std::size_t deep_movers = 0;
  int build_stages = 0;  // stages its build took (Bed3dBuild::stage when it finished)
};

// The packing fraction for people: "0.581", or why there is none (NaN: a bed under about four diameters
// deep has no interior to measure it in).
std::string packing_text(const Bed3d& bed);

// How still a bed left alone for an impact's duration must hold, or "ejecta" would be the bed moving: no
// grain may move more than 2.5 % of a diameter, nor be faster than 1 cm/s times sqrt(r / 1 cm) (speeds
// of a bed settling under gravity scale so). The thesis-sized bed's: 0.05 cm and 1 cm/s, the 2-D limits.
struct AtRestLimits {
  double displacement = 0, speed = 0;
  // Whether a grain that moved `moved` and ends at `speed_now` breaks a limit (the checks pass at a limit).
  bool broken_by(double moved, double speed_now) const { return moved > displacement || speed_now > speed; }
};
AtRestLimits at_rest_limits(const Bed3dSpec& spec);

// The times the build held a bed still settling after its last probe (see build_bed3d).
int build_holds(const Bed3d& bed);

// A bed part-way through its build: the spheres at rest after the first `stage` of build_bed3d's stages
// (the pour, ten stiffening steps, damping, relaxing, up to eight probes for spheres still moving, then
// if the probes ran out, up to four holds)
// and the build's counts so far. Each stage starts from spheres at rest, so a build continued from here
// makes, bit for bit, the bed a build that never stopped would.
struct Bed3dBuild {
  int stage = 0;
  bool finished = false;
  std::vector<Body3Spec> bodies;
  std::size_t removed = 0, probes = 0, deep_movers = 0;
  double seconds = 0;  // computing time so far
  // A stage part-way through (a probe of a 20,000-sphere sand bed runs for hours). `bodies` and the counts
  // above are then the stage's start; `runs_done` holds how each of the stage's finished runs of the bed
  // left the spheres (kStageRunColumns, in run order), and `run_under_way` the world of the run it was in
  // (World3d::save_state under kStageWorld). Both empty: the stage has not begun.
  SampleTable runs_done;
  std::map<std::string, SampleTable> run_under_way;
};
// A finished run's row per sphere: the run's index within its stage, then the sphere's state.
extern const std::vector<std::string> kStageRunColumns;
inline constexpr const char* kStageWorld = "stage/world/";

// A build's counts as a finished bed keeps them, and back (the spheres aside): what a checkpoint writes
// for either.
void keep_build_record(Bed3d& bed, const Bed3dBuild& b);
Bed3dBuild build_record(const Bed3d& bed);

// Pours and settles a bed (seconds to a minute of computing for the thesis's beds; an hour or more for a
// 20,000-sphere sand bed). `log`, when given, hears of each stage as it ends (pour, stiffening, damping,
// each probe for spheres still moving, each hold), with the time so far. The build starts from `from` (a
// fresh one: the pour; or a stage part-way through) and hands its state to `after_stage` after every
// stage, and within a stage every `save_every` seconds of computing, so a long build can be checkpointed
// and continued to the same bed, bit for bit.
// Under mpirun every rank must call it for the same bed: a bed of spheres is then spread over the ranks
// (the same bits as on one rank, docs/parallel.md), unless `ranks` asks each rank to build it alone.
enum class BedRanks { spread, each_alone };
Bed3d build_bed3d(const Bed3dSpec& spec, const std::function<void(const std::string&)>& log = {},
                  Bed3dBuild from = {}, const std::function<void(const Bed3dBuild&)>& after_stage = {},
                  double save_every = 600, BedRanks ranks = BedRanks::spread);
// The bed build_bed3d makes around `bodies` (its spheres at rest), without the build's statistics: the
// same scene, top and packing, so a bed kept in a checkpoint gives the same impacts bit for bit.
Bed3d bed3d_from_bodies(const Bed3dSpec& spec, std::vector<Body3Spec> bodies);

struct Ejectum3d {
  std::int64_t id = -1;
  double mass = 0;                // g (a sieved bed's grains differ)
  double x0 = 0, y0 = 0, z0 = 0;  // where it sat, relative to the impact point (cm)
  double vx = 0, vy = 0, vz = 0;  // when its centre crossed top + 2 r_b (cm/s)
  double vz_launch = 0;           // vz carried back ballistically to its original centre height
  double time = 0;
};

struct Impact3dResult {
  double x_impact = 0, y_impact = 0, z_impact = 0;
  bool rebounded = false;
  double vx = 0, vy = 0, vz = 0;  // incident grain where it left the bed (vz carried back to there)
  double incident_speed = 0, alpha_deg = 0, incident_mass = 0, bed_mass = 0, g = 981;
  std::vector<Ejectum3d> ejecta;
  double steps = 0, wall_seconds = 0;
};

// The bed alone for `duration` on `engine` (impulse engines at `rigid_dt`): how far it moves.
BedHold hold_bed3d(const Bed3d& bed, const std::string& engine, double duration, double rigid_dt);

// The bed as `engine` holds it. An impulse engine resolves the overlaps of a bed built on the soft-contact
// engine its own way, so the bed sinks further on it (the 2,000-sphere thesis bed 0.1-0.13 cm on ODE and
// Bullet). Left alone on the engine for `settle` s from rest and stopped where it is, up to `rounds`
// times, until a hold of `duration` s passes at_rest_limits, the bed becomes that engine's own bed at rest.
// `log` (if set) hears a line per hold: each takes minutes on a bed of thousands of spheres.
struct EngineBed {
  Bed3d bed;
  BedHold hold;     // the last hold, on the engine
  int settles = 0;  // 0: the bed was at rest on the engine as built
};
EngineBed settle_on_engine(const Bed3d& bed, const std::string& engine, double settle, int rounds,
                           double duration, double rigid_dt,
                           const std::function<void(const std::string&)>& log = {});
// The same from a bed whose hold on the engine is already known (`start.hold`, `start.settles` = 0), so
// that hold is not run twice.
EngineBed settle_on_engine(EngineBed start, const std::string& engine, double settle, int rounds,
                           double duration, double rigid_dt,
                           const std::function<void(const std::string&)>& log = {});

// The grains of a hold that break a limit (0: the bed is at rest).
std::size_t grains_over(const BedHold& h, const AtRestLimits& limits);
// Where a 3-D hold's movers are, for a person deciding whether the motion matters to an impact at the top:
// "3 spheres over a limit; the one that moved most (0.25 cm) sits 8.69 cm below the top".
std::string where_the_bed_moved(const BedHold& h, const AtRestLimits& limits);

// Impact number `run` of case `c` on `bed` on o.engine (an impulse engine steps at o.rigid_dt): the point is
// drawn from Rng(seed, run).
Impact3dResult run_impact3d(const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, std::size_t run,
                            const ImpactOptions& o = {});

// One impact as a fixed-width row of numbers (MPI gathering, checkpoints): kImpact3dHead numbers (impact
// point, rebounded, rebound velocity, incident speed, angle and mass, bed mass, g, steps, wall seconds),
// then kImpact3dPerEjectum per ejectum (id, mass, x0, y0, z0, vx, vy, vz, vz_launch, time), NaN after the
// last, kMaxEjecta of them.
inline constexpr std::size_t kImpact3dHead = 14, kImpact3dPerEjectum = 10;
std::vector<double> impact3d_row(const Impact3dResult& r);
Impact3dResult impact3d_from_row(const std::vector<double>& row);

// Means with intervals over impacts, under the 2-D summary's names where the quantity is the same
// (eps_ix, eps_iy (vertical), eps_i, theta_i, ejected, reptation, ej_speed, ej_vy (vertical), ej_angle
// (from the vertical)) and 3-D ones: eps_iz (the rebound's sideways velocity / v_i), ej_azimuth (degrees
// from +x, -180..180), ej_sideways (|sin| of the azimuth: 0 along the incident plane, 1 across it),
// ej_sin_azimuth (signed: +y or -y),
// ej_backward (1 if thrown upwind), ej_energy (ejected kinetic energy at launch / incident, as in 2-D).
struct Impact3dSummary {
  std::map<std::string, MeanInterval> q;
  std::size_t impacts = 0, rebounds = 0, ejecta = 0;
  double median_wall_seconds = 0, mean_steps = 0;
};
Impact3dSummary summarize_impacts3d(const std::vector<Impact3dResult>& r);

// `runs` impacts of case `c`, dealt out over the MPI ranks (the same on any rank count); impact i on bed
// i mod the number of beds.
std::vector<Impact3dResult> run_impact3d_ensemble(
    const std::vector<Bed3d>& beds, const ImpactCase& c, std::uint64_t seed, std::size_t runs,
    const ImpactOptions& o, const std::function<void(std::size_t, std::size_t)>& progress = {});
std::vector<Impact3dResult> run_impact3d_ensemble(
    const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, std::size_t runs, const ImpactOptions& o,
    const std::function<void(std::size_t, std::size_t)>& progress = {});
// The impacts numbered `indices` (each as run_impact3d's `run`), dealt out over the ranks: the same
// results as those entries of an ensemble.
std::vector<Impact3dResult> run_impact3d_indices(
    const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, const std::vector<std::size_t>& indices,
    const ImpactOptions& o, const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace grainlab::validation
