// `grainlab ripples continuum [--speed V] [--out F.h5] [--json]`: the continuum model of Ch. V section 1: the
// finite-difference solver's growth rates beside the anti-diffusion equation's, and the steady shapes of
// eqs 5.7-5.8 (closed form and RK4).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "continuum.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "ripples_commands.hpp"

namespace grainlab::cli {

using namespace grainlab::ripples;

int continuum_command(const RipplesCommands& a) {
  refuse_existing_out(a.out, a.force);
  const ContinuumParams p;
  // Growth: a tiny sine of 1..8 waves on 64 cells, 200 explicit steps.
  SampleTable growth{"growth",
                     "per wavelength (cm): growth rate (1/s) measured from the finite-difference solver, "
                     "predicted for the discrete scheme, and the continuum's D k^2",
                     {"wavelength", "measured", "discrete", "continuum"},
                     {}};
  const int n = 64, steps = 200;
  for (int waves = 1; waves <= 8; ++waves) {
    const double k = 2 * M_PI * waves / (n * p.dx);
    std::vector<double> h(n);
    for (int i = 0; i < n; ++i) h[static_cast<std::size_t>(i)] = 1e-9 * std::sin(k * i * p.dx);
    advance_continuum(p, h, steps);
    double amp = 0;
    for (int i = 0; i < n; ++i) amp += 2.0 / n * h[static_cast<std::size_t>(i)] * std::sin(k * i * p.dx);
    growth.rows.push_back({n * p.dx / waves, (std::pow(amp / 1e-9, 1.0 / steps) - 1) / p.dt,
                           (continuum_growth_per_step(p, k) - 1) / p.dt, p.anti_diffusivity() * k * k});
  }
  // Steady shapes at speed v: C = -0.01, 0, +0.01 cm about the flat one.
  const double v = a.shape_speed, lambda = steady_length(p, v);
  const int points = 200;
  const double ds = 3 * lambda / points;
  SampleTable shapes{
      "shapes",
      "eq. 5.8 at s = x - v t (cm): h (cm) for C = -0.01, 0, +0.01 cm, and the largest difference "
      "from eq. 5.7 integrated by RK4",
      {"s", "h_below", "h_flat", "h_above"},
      {}};
  double worst = 0;
  const double flat = steady_shape(p, v, 0, 0, 0);
  std::vector<std::vector<double>> rk;
  for (const double C : {-0.01, 0.0, 0.01})
    rk.push_back(integrate_steady_shape(p, v, 0, flat + C, ds, points));
  for (int i = 0; i <= points; ++i) {
    std::vector<double> row{i * ds};
    int c = 0;
    for (const double C : {-0.01, 0.0, 0.01}) {
      const double h = steady_shape(p, v, C, 0, i * ds);
      worst = std::max(worst, std::abs(h - rk[static_cast<std::size_t>(c++)][static_cast<std::size_t>(i)]));
      row.push_back(h);
    }
    shapes.rows.push_back(row);
  }
  if (!a.out.empty())
    write_sample_tables(a.out, {growth, shapes},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", "the thesis's continuum surface evolution (Ch. V section 1)"},
                         {"parameters", fmt::format("F_x {} /(cm^2 s), a {} cm, d {} cm, alpha {} deg, dx {} "
                                                    "cm, dt {} s, v {} cm/s",
                                                    p.F_x, p.a, p.d, p.alpha_deg, p.dx, p.dt, v)}});
  if (a.json) {
    nlohmann::json g = nlohmann::json::array();
    for (const auto& r : growth.rows)
      g.push_back({{"wavelength", r[0]}, {"measured", r[1]}, {"discrete", r[2]}, {"continuum", r[3]}});
    fmt::print("{}\n", nlohmann::json{{"anti_diffusivity", p.anti_diffusivity()},
                                      {"growth", g},
                                      {"speed", v},
                                      {"lambda", lambda},
                                      {"flat_height", flat},
                                      {"rk4_max_difference", worst}}
                           .dump(2));
    return 0;
  }
  fmt::print(
      "continuum surface evolution (eqs 5.3-5.8): anti-diffusivity D = a d^2 F_x / tan(alpha) = {:.4g} "
      "cm^2/s\n  growth rates (1/s): wavelength, measured, discrete scheme, continuum D k^2\n",
      p.anti_diffusivity());
  for (const auto& r : growth.rows)
    fmt::print("    {:6.2f} cm  {:10.4g}  {:10.4g}  {:10.4g}\n", r[0], r[1], r[2], r[3]);
  fmt::print(
      "  steady shapes at v = {} cm/s: lambda = {:.4g} cm, flat at h0 + {:.4g} cm; others steepen as "
      "exp(s / lambda) (eq. 5.8; RK4 of eq. 5.7 agrees to {:.1e} cm)\n",
      v, lambda, flat, worst);
  return 0;
}

}  // namespace grainlab::cli
