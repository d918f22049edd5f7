#pragma once
// One grain-bed impact (thesis Ch. III): an incident grain released just above a bed, followed for
// 0.07 s, its rebound and every ejected bed grain recorded. Definitions (docs/impacts.md):
// - top of the bed: the highest point of the bed's surface in its middle 80 % (BedSurface::top);
// - ejected: a grain whose centre rises above top + 2 r_b (one diameter above the top) while moving up;
//   its velocity is recorded there (as the thesis did) and also carried ballistically back to its
//   original centre height (the launch velocity, for the splash function);
// - rebound: the incident grain crossing the same height; its rebound velocity is carried back to
//   where it last touched the bed. A grain that never gets there within the run is "nabbed".
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ensemble.hpp"
#include "h5_output.hpp"
#include "impact_bed.hpp"

namespace grainlab::validation {

// Table 3.1.
struct ImpactCase {
  std::string name;
  double speed = 3000, alpha_deg = 15, mu = 0.5;
  std::string bed = "loose";
  double radius = 1.0;
  // Table 3.1's cases fix m_i / m_b as the discs' (r_i / r_b)^2 (m_b / 4 for H and I, so that H has A's
  // incident energy): a sphere standing in for a disc keeps it. false: the grain has the bed's density.
  bool disc_mass_ratio = false;
};
const std::vector<ImpactCase>& impact_cases();
// Throws InputError naming the allowed cases.
const ImpactCase& impact_case(const std::string& name);

struct ImpactOptions {
  std::string engine = "native";
  double duration = 0.07;         // followed after release (s)
  double steps_per_contact = 30;  // Verlet: dt = shortest contact time / this
  double check_interval = 1e-4;   // s between looks at the grains
  double window = 0.3;            // impact points uniform over this middle fraction of the bed
  double rigid_dt = 1e-5;         // the step of impulse engines (Box2D, ODE, Bullet): no contact to resolve
  std::string record;             // non-empty: also write this impact as a run file (ParaView)
  bool overwrite = false;
  // 3-D, native engine: only the bed grains whose centres lie within this distance (cm) of the impact
  // point move; the rest are held in place (Body3Spec::held), so an impact costs what its neighbourhood
  // costs, not the whole bed. 0: every grain moves. docs/impacts.md "An impact's active zone" measures
  // what it changes.
  double active_radius = 0;
};

enum class GrainType : int { Other = 0, Target = 1, Brink = 2, AntiBrink = 3 };

struct Ejectum {
  std::int64_t id = -1;
  GrainType type = GrainType::Other;
  double x0 = 0, y0 = 0;                // where it sat, relative to the impact point (cm)
  double vx = 0, vy = 0;                // at top + 2 r_b (cm/s)
  double vx_launch = 0, vy_launch = 0;  // carried back to its original centre height
  double time = 0;                      // when it crossed
};

struct ImpactResult {
  double x_impact = 0, y_impact = 0;  // the first contact point (cm)
  double beta_deg = 0;                // from the vertical, positive on the target's upstream face
  std::int64_t target = -1;
  bool rebounded = false;
  double vx = 0, vy = 0, spin = 0;  // incident grain where it left the bed (cm/s, rad/s)
  double incident_speed = 0, alpha_deg = 0, incident_mass = 0, bed_mass = 0, incident_radius = 0;
  std::vector<Ejectum> ejecta;
  double bed_kinetic_before = 0;  // bed's kinetic energy / incident kinetic energy at release
  double steps = 0, wall_seconds = 0, top = 0;
  double g = 981;  // the scene's gravity (cm/s^2): ballistic ranges and launch speeds use it
};

// Impact number `run` of case `c` on `bed`: the impact point is drawn from Rng(seed, run).
ImpactResult run_impact(const Bed& bed, const ImpactCase& c, std::uint64_t seed, std::size_t run,
                        const ImpactOptions& o = {});

// Shared by the 2-D and 3-D impacts: the impact's scene run again and written to o.record with 1 ms frames
// (ParaView), when o.record is set; and the final frame of `bed_scene` left alone for `duration` on
// `engine` (impulse engines at `rigid_dt`).
void record_impact(const Scene& scene, const ImpactOptions& o);
Frame bed_left_alone(const Scene& bed_scene, const std::string& engine, double duration, double rigid_dt);

// Quantities of one impact in the thesis's notation (Tables 3.2-3.6), NaN where undefined (no rebound).
// The per-ejectum quantities (speeds, angles, origins) are pooled over all ejecta by summarize_impacts.
struct ImpactMeasures {
  double eps_ix, eps_iy, eps_i, theta_i, xi_i, beta;  // Table 3.2
  double eps_bx, eps_by, theta_b, m_beff;             // Table 3.3 (m_beff / m_b, two-body)
  double reptation, ejected;                          // Table 3.4, per event
  double ej_px, ej_py;                                // Table 3.5: ejected momentum (g cm/s)
  double ej_energy;                                   // ejected kinetic energy / incident
  double rebounded;                                   // 1 or 0
};
ImpactMeasures measure_impact(const ImpactResult& r, double restitution);

// m_beff / m_i from one rebound: the two-body law of eq. 3.A.1 solved for the mass ratio, with the
// measured contact angle beta (the thesis's way to Table 3.3).
double effective_mass_two_body(double alpha_deg, double beta_deg, double eps_ix, double eps_iy,
                               double restitution);

}  // namespace grainlab::validation

namespace grainlab::validation {

// How well an engine holds a bed at rest with nothing hitting it: the bed alone for `duration`.
struct BedHold {
  double max_displacement = 0;  // cm, largest of any disc
  double max_speed = 0;         // cm/s, largest of any disc at the end
  double kinetic_energy = 0;    // erg at the end
  // 3-D beds (hold_bed3d), per body in the scene's order: displacement (cm), speed at the end (cm/s) and
  // how deep its centre sits below the bed's top (cm), so a report can say which grains moved and where.
  std::vector<double> displacement, speed, depth;
};
BedHold hold_bed(const Bed& bed, const std::string& engine, double duration, double rigid_dt);
// Throws InputError (a capability error) when the bed moved: a disc faster than 1 cm/s (it would rise
// 0.5 mm, far below the 2 cm of an ejection) or one displaced by more than 0.05 cm (2.5 % of a diameter).
// The displacement limit is a judgement, set after measuring the engines (docs/impacts.md): ODE moves the
// loose bed 0.009 cm, Bullet 0.034, Box2D 0.056; 0.01 cm would also exclude Bullet.
void check_bed_held(const BedHold& h, const std::string& engine);

// `runs` impacts of case `c`, run i on bed i % beds.size() with Rng(seed, i), dealt out over the MPI
// ranks (the result is the same on any rank count). An impact ejecting more than kMaxEjecta grains keeps
// the first kMaxEjecta (counted in `ejecta_dropped`).
inline constexpr std::size_t kMaxEjecta = 160;
struct ImpactEnsemble {
  std::vector<ImpactResult> impacts;
  std::size_t ejecta_dropped = 0;
};
// With a `checkpoint` path, every finished impact is kept in that file as the ensemble goes
// (ensemble_checkpoint.hpp), and the impacts found there are taken from it: the same command run again
// continues a stopped ensemble, or a finished one to more runs, to the numbers of one that never stopped.
// The file's fingerprint holds the case, the seed, the options and a digest of every bed, so impacts on
// another bed or case are refused (InputError, key --checkpoint), never mixed in.
ImpactEnsemble run_impact_ensemble(const std::vector<Bed>& beds, const ImpactCase& c, std::uint64_t seed,
                                   std::size_t runs, const ImpactOptions& o,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {},
                                   const std::string& checkpoint = {});

}  // namespace grainlab::validation

#include <map>

namespace grainlab::validation {

// Means with intervals of every quantity of Tables 3.2-3.5 and 3.9 over an ensemble. Per-impact keys:
// eps_ix eps_iy eps_i theta_i xi_i beta eps_bx eps_by theta_b m_beff (rebounds only), ejected reptation
// ej_px ej_py ej_energy (every impact). Per-ejectum keys, pooled over all ejecta: ej_speed ej_vy ej_angle
// origin_x origin_y origin_r, and ej_angle_<type>, ej_pex_<type> (type: target, brink, antibrink, other;
// p_ex per ejectum over the incident horizontal momentum).
struct ImpactSummary {
  std::map<std::string, MeanInterval> q;
  std::size_t impacts = 0, rebounds = 0, ejecta = 0;
  double median_wall_seconds = 0, mean_steps = 0;
};
ImpactSummary summarize_impacts(const std::vector<ImpactResult>& r, double restitution);
// m_beff / m_b from the rebounds' mean eps_ix, eps_iy and beta through the two-body law (the summary's
// "m_beff"; "m_beff_per_impact" averages single inversions), with a bootstrap 95 % interval; sd is the
// single-impact spread the bootstrap implies.
MeanInterval effective_mass_of_means(const std::vector<ImpactResult>& r, double restitution);
// m_beff(a) - m_beff(b) for two cases run with the same seed (impact i at the same point in both), with
// a paired bootstrap 95 % interval.
MeanInterval effective_mass_difference(const std::vector<ImpactResult>& a, const std::vector<ImpactResult>& b,
                                       double restitution);

// The thesis's mean and half-width for a case and key (Tables 3.2-3.5, 3.7-3.9); none if not printed.
std::map<std::string, std::pair<double, double>> thesis_impact_values(const std::string& case_name);

}  // namespace grainlab::validation
