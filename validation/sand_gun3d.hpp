#pragma once
// The thesis's sand-gun experiment (Ch. III section 6, Tables 3.11-3.12) with spheres (issue #15): single
// grains of a sieved sand shot at 600-1200 cm/s, 10-21 degrees below the horizontal, into a bed of the
// same sand, on the native 3-D engine. The rows are the tables' (saltation::sand_gun_splash()); the
// quantities are measured as the experiment's strobe photographs measured them (a 2-D projection onto
// the incident plane x-z), with the rebound and ejecta rules of impacts.hpp.
//
// The material (docs/impacts.md "The sand-gun experiment with spheres" says why):
// - diameters uniform over the sieve's 0.071-0.085 cm (the incident grain: the mean, 0.078 cm);
// - quartz, 2.65 g/cm^3; friction 0.5; pair restitution 0.85 (the thesis's grains);
// - k_n = k_s = 2e7 dyn/cm: a head-on pair at the fastest shot (1200 cm/s) overlaps 6 % of a diameter,
//   inside the 3-9 % of the thesis's own cases; quartz (Hertz, E = 70 GPa) would overlap 0.6 % and cost
//   10x the steps. `grainlab sand-gun --stiffness 4` measures what the stiffness changes (docs/impacts.md).
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ensemble.hpp"
#include "impacts3d.hpp"

namespace grainlab::validation {

// One row of Tables 3.11-3.12: the shot, the experiment's values and how many events it had.
struct SandGunRow {
  std::size_t index = 0;  // 1-9, the tables' order
  double speed = 0, alpha_deg = 0;
  std::size_t events = 0;
  // The experiment's means (cm, cm/s, degrees), and the spread (sd) of those the table gives one for.
  std::map<std::string, double> measured, measured_sd;
};
const std::vector<SandGunRow>& sand_gun_rows();

// The sand bed: `count` spheres in a width x depth box (x along the shot). A 20,000-sphere bed is
// 5.0 x 2.5 cm and about 10 diameters deep.
Bed3dSpec sand_gun_bed_spec(int count, double stiffness_factor = 1);

// The row as an impact case (the incident grain the sieve's mean size) and the options that follow the
// impact for the thesis's 0.07 s scaled to the grain (sqrt(r / 1 cm)).
ImpactCase sand_gun_case(const SandGunRow& row);
ImpactOptions sand_gun_options(const Bed3dSpec& bed);

// Table 3.11-3.12's quantities of one row's impacts, under the names of SandGunRow::measured:
// eps_ix, eps_iy, theta_i (rebound), energy_ratio (E_out / E_in of the rebound: mean eps_i^2),
// ejecta (per event), reptation_event (cm: sum over an event's ejecta of 2 v_x v_z / g), reptation
// (per ejectum, cm), ej_vz (vertical velocity, cm/s), theta_e (ejection angle from the vertical, in the
// incident plane, degrees), plus 3-D ones: ej_sideways, eps_lateral.
//
// `visible_above` (in bed-grain diameters d) is how high above the top of the bed an ejectum's centre
// must rise to be counted. 1 is the thesis's rule for its simulations, and grainlab's. The photographs
// counted only what rose into view: their apparent bed surface, the highest grains along the line of
// sight, stood "a few grain diameters" above the true bed level at the impact (thesis Ch. III section 6),
// and a grain moving against a bed of identical grains is lost in it. With visible_above > 1, an ejectum
// whose apex stays below top + visible_above d is left out of every ejecta quantity; that needs the bed
// grains' diameter d (cm, > 0; std::invalid_argument otherwise). Without the two, every ejectum counts.
std::map<std::string, MeanInterval> sand_gun_quantities(const std::vector<Impact3dResult>& impacts);
std::map<std::string, MeanInterval> sand_gun_quantities(const std::vector<Impact3dResult>& impacts,
                                                        double visible_above, double diameter);

// A power law y = a x^n fitted by weighted least squares to the logs of positive means (weights from
// their intervals): the exponent and its 95 % half-width.
struct PowerLaw {
  double exponent = 0, half_width = 0;
};
PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<MeanInterval>& y);
// The same for the table's own means (no intervals: an unweighted fit, half-width 0).
PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

struct SandGunRun {
  Bed3d bed;
  double visible_above = 1;  // the ejecta counting rule of `quantities` (sand_gun_quantities)
  double active_zone = 0;    // bed-grain diameters about each impact point that moved (0: the whole bed)
  std::vector<SandGunRow> rows;
  std::vector<std::vector<Impact3dResult>> impacts;  // per row
  std::vector<std::map<std::string, MeanInterval>> quantities;
};

// What a sand-gun checkpoint keeps: the bed (built, or part-way through its build) and each finished
// impact by (row 1-9, run index).
struct SandGunProgress {
  Bed3dBuild build;  // while build.finished is false, the bed is not yet built (only bed.spec is set)
  Bed3d bed;
  std::map<std::pair<std::size_t, std::size_t>, Impact3dResult> done;
};
// Writes the checkpoint atomically (validation/sand_gun_checkpoint.cpp). `impacts_of`, when set, names
// what else decides the impacts (`grainlab impact` keeps one case's impacts, on one engine, in this form)
// and joins the file's fingerprint.
void write_sand_gun_checkpoint(const std::string& path, const SandGunProgress& p, std::uint64_t seed,
                               const std::string& impacts_of = {});
// Reads it back: nullopt if `path` does not exist; InputError (key --checkpoint) if it is damaged, not a
// sand-gun checkpoint, or written for another bed spec or seed, or for another `impacts_of` while it
// holds impacts (a file with a built bed and no impacts serves any `impacts_of`: the bed is the same).
std::optional<SandGunProgress> read_sand_gun_checkpoint(const std::string& path, const Bed3dSpec& spec,
                                                        std::uint64_t seed,
                                                        const std::string& impacts_of = {});

// The bed of `kept` (read from a checkpoint, or fresh) to `spec`, built now, or finished, if it is not yet;
// with a `checkpoint` path the file is rewritten (rank 0) after each stage of the build. Afterwards
// kept.bed is the bed and kept.build is marked finished.
void finish_checkpointed_bed(SandGunProgress& kept, const Bed3dSpec& spec, std::uint64_t seed,
                             const std::function<void(const std::string&)>& log,
                             const std::string& checkpoint, const std::string& impacts_of = {});
// Impacts 0..runs-1 of case `c` on `bed`, kept in `kept.done` under key `row`: those already there as they
// are, the rest computed a round (one per rank) at a time, each round added and the file rewritten.
std::vector<Impact3dResult> checkpointed_impacts(SandGunProgress& kept, std::size_t row, const Bed3d& bed,
                                                 const ImpactCase& c, std::size_t runs, std::uint64_t seed,
                                                 const ImpactOptions& o, const std::string& checkpoint,
                                                 const EnsembleProgress& progress,
                                                 const std::string& impacts_of = {});
// The same for one case on a bed the caller built (the suite's Table 3.1 cases), kept in a file of its own
// at `checkpoint` (empty: none, the ensemble is run as it is). The file's fingerprint holds the case, the
// options and the bed's spheres, so a file written for another bed (another binary's build, an engine's
// own settled bed) is refused with InputError (key --sand-gun-checkpoint) instead of lending its impacts.
std::vector<Impact3dResult> kept_case_impacts(const std::string& checkpoint, const Bed3d& bed,
                                              const ImpactCase& c, std::size_t runs, std::uint64_t seed,
                                              const ImpactOptions& o, const EnsembleProgress& progress);

// Builds the bed and runs `runs` impacts of each row (`rows`: 1-based indices; empty: all nine), spread
// over the MPI ranks. With a `checkpoint` path, the bed (or its build so far) and the impacts already in that
// file are taken from it, and the file is rewritten (rank 0) after each stage of the bed's build and after
// each round of impacts (one per rank), so a run stopped at any point continues from there to the same
// numbers.
// `active_zone` (bed-grain diameters; 0: none): only the grains within it of each impact point move
// (ImpactOptions::active_radius); it joins the checkpoint's fingerprint, so a file's impacts are never
// mixed across zones (a file that holds a bed and no impacts yet serves any zone). `runs` 0: only the bed.
SandGunRun run_sand_gun(const Bed3dSpec& bed, const std::vector<std::size_t>& rows, std::size_t runs,
                        std::uint64_t seed, const std::function<void(const std::string&)>& log = {},
                        const EnsembleProgress& progress = {}, const std::string& checkpoint = {},
                        double active_zone = 0);
// What the impacts of a sand-gun run depend on besides the bed and the seed (the checkpoint's
// `impacts_of`): the active zone in bed-grain diameters, empty without one. Every checkpoint that keeps
// impacts appends it to its own `impacts_of` (after a space) when a zone is set.
std::string sand_gun_impacts_of(double active_zone);
constexpr const char* kActiveZoneKey = "active_zone";  // how sand_gun_impacts_of's text begins

// Tables 3.11 and 3.12 with grainlab's spheres beside the experiment: one row per shot, each cell
// "mean [95 % interval] (experiment)"; then the fitted exponents of ejecta per event, ejection velocity and
// reptation per ejectum in v_i over the rows at 15-16 degrees (markdown).
std::string sand_gun_markdown(const SandGunRun& run);

// The quantities again with ejecta counted only when they rise `visible_above` bed-grain diameters above
// the top of the bed (sand_gun_quantities).
void recount_sand_gun(SandGunRun& run, double visible_above);

// The rows at 15-16 degrees (the speed series 650-1200 cm/s) of a run, as indices into run.rows.
std::vector<std::size_t> sand_gun_speed_series(const SandGunRun& run);
// The exponent n of quantity `key` ~ v_i^n over the speed series: grainlab's (weighted by its intervals)
// and the experiment's (its means).
std::pair<PowerLaw, PowerLaw> sand_gun_exponent(const SandGunRun& run, const std::string& key);

}  // namespace grainlab::validation
