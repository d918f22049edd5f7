#include "suites.hpp"

#include "ensemble_checkpoint.hpp"

namespace grainlab::validation {

std::vector<std::vector<double>> suite_ensemble(const SuiteOptions& o, const std::string& name,
                                                std::size_t runs, std::size_t width,
                                                const std::function<std::vector<double>(std::size_t)>& run) {
  EnsembleCheckpoint kept;
  if (!o.ensembles_dir.empty())
    kept = {o.ensemble_checkpoint(name), "suite's ensemble checkpoint", "ensemble " + name,
            "was written for another ensemble: run validate without --resume"};
  return run_checkpointed_ensemble(runs, width, run, kept, o.progress);
}

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {
      {"thesis-code",
       "the thesis's Ch. II code checks: Table 2.1, spin loss, conservation, sorting (Fig. 2.11)",
       run_thesis_code_suite, 0.05},
      {"single-body", "one body, analytic answers, on every engine: free flight, bounce, incline, rolling",
       run_single_body_suite, 0.2},
      {"loaded-die",
       "the thesis's loaded 2-D die on every engine: p_h against loading and restitution, beside Appendix "
       "II.1",
       run_loaded_die_suite, 1.3},
      {"tumbling-polygon",
       "square, rectangle and hexagon dropped on an incline on every 2-D engine: settled motion, Coulomb "
       "sliding, the pivot rule, terminal rolling",
       run_tumbling_polygon_suite, 0.4},
      {"block-incline",
       "the thesis's 5 x 5 x 1 cm block rolling down a 40 degree incline on the 3-D engines: rotational "
       "energy per body axis (Fig. 2.10)",
       run_block_incline_suite, 0.2},
      {"pair-impact",
       "two discs and two spheres colliding at the Ch. III scale on every engine: restitution, rebound and "
       "spin against Walton's rigid-body model",
       run_pair_impact_suite, 0.01},
      {"stability",
       "hard cases on every engine: stiff and soft contacts, mass ratio 1:1000, polygons vertex on vertex, "
       "restitution 0 and 1, grazing impacts, a grain into a bed at 8100 cm/s, adaptive step underflow",
       run_stability_suite, 0.5},
      {"impacts",
       "the thesis's grain-bed impacts (Tables 3.1-3.9) with intervals on loose and dense beds, its "
       "statements as "
       "checks, the rebound model (Appendix III.1), and the impulse engines that can hold the bed",
       run_impacts_suite, 1.9},
      {"impacts-3d",
       "Ch. III's impacts with spheres beside discs (issue #15): energy and the symmetry across the incident "
       "plane checked, rebound and ejecta set beside 2-D and the thesis",
       run_impacts_3d_suite, 1.7},
      {"saltation",
       "the thesis's Ch. IV saltation models: the conveyor belt (Tables 4.1-4.2), the wind-driven model's "
       "identities, Tables 4.4 and 4.5, CASE 1's text numbers and the flux law",
       run_saltation_suite, 0.4},
      {"ripples",
       "the thesis's Ch. V ripple models: worms, triangular collisions, the continuum, Haff's bin model, "
       "the lattice-bed runs of Figs 5.22-5.23 as seed ensembles, the limiting wavelength",
       run_ripples_suite, 0.05},
      {"dem-saltation",
       "saltation from first principles: a periodic DEM bed under a wind the grains slow down (effect "
       "wind_drag): momentum balance, flux against u*, impact speeds, stiffness independence, the Ch. IV "
       "model with the DEM's own splash",
       run_dem_saltation_suite, 4.9},
      {"hybrid",
       "the 3-D hybrid ripple model (Huo et al. 2021): drag limits, mid-air collisions, the Lammel splash's "
       "moments, the grain-free wind, flux on a flat bed against eq. 31, ripple growth, coarsening, ripple "
       "index and migration, the initial wavelength against u*, beds of two sizes",
       run_hybrid_suite, 1.0},
  };
  return all;
}

const Suite* find_suite(const std::string& name) {
  for (const Suite& s : suites())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace grainlab::validation
