#include "accuracy_cost.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "engine.hpp"
#include "ensemble.hpp"
#include "h5_output.hpp"
#include "loaded_die.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

// Runs `toml` with `sets` on the setting's engine to `until`, calling `sample` (if given) every `every`
// seconds; returns the engine for the caller to read, with cost counters filled into `m`.
std::unique_ptr<Engine> run(const CostSetting& s, const std::string& toml, double until, CostMeasurement& m,
                            const std::function<void(const Engine&)>& sample = {}, double every = 0) {
  auto e = engine_for(s.engine, toml, s.sets);
  if (sample && every > 0) {
    for (double t = every; t < until + 0.5 * every; t += every) {
      e->advance_to(std::min(t, until));
      sample(*e);
    }
  } else {
    e->advance_to(until);
  }
  const auto d = e->diagnostics();
  m.steps = d.at("steps");
  m.rejected = d.at("rejected_steps");
  if (d.count("force_evaluations") && engine_capabilities(s.engine).soft_contacts)
    m.iterations = d.at("force_evaluations");
  for (const char* k : {"solver_velocity_iterations", "solver_iterations"})
    if (d.count(k) && s.method != "ode step") m.iterations = m.steps * d.at(k);
  return e;
}

// The curves every scene sweeps: native Verlet over dt, the predictor-corrector over its tolerance,
// native stiffness where it is a modelling choice, and each impulse engine over dt, solver iterations
// and (Bullet) sub-steps, ODE with both steppers.
struct Sweep {
  std::vector<double> native_dt, tolerance, stiffness, impulse_dt;
  double pc_dt_max = 1e-3;    // a tenth of the scene's contact duration (docs/scenes.md: keep it below)
  std::string stiffness_key;  // e.g. "materials.m.k_n" (and k_s alongside); empty: no stiffness curve
  // ODE's direct stepper solves one dense LCP per step: 180 s for 500 steps of 150 discs, measured; it is
  // left out where there are many bodies (its cost there is that line, not a curve).
  bool ode_direct = true;
};

std::vector<CostSetting> settings_for(const Sweep& w, bool quick) {
  std::vector<CostSetting> out;
  auto add = [&](const std::string& engine, const std::string& method, const std::string& knob, double value,
                 std::vector<std::string> sets) {
    out.push_back({engine, method, knob, value, std::move(sets)});
  };
  for (double dt : w.native_dt)
    add("native", "native verlet", "dt", dt,
        {"accuracy.integrator=\"verlet\"", fmt::format("accuracy.dt={}", dt)});
  for (double tol : w.tolerance)
    add("native", "native predictor-corrector", "tolerance", tol,
        {"accuracy.integrator=\"predictor-corrector\"", fmt::format("accuracy.tolerance={}", tol),
         fmt::format("accuracy.dt={}", w.native_dt.back()), fmt::format("accuracy.dt_max={}", w.pc_dt_max)});
  if (!w.stiffness_key.empty() && !quick)
    for (double k : w.stiffness)
      add("native", "native verlet, stiffness", "k_n", k,
          {"accuracy.integrator=\"verlet\"",
           // 40 steps per contact of the stiffest spring's own duration scale
           fmt::format("accuracy.dt={}", w.native_dt.back() * std::sqrt(w.stiffness.back() / k)),
           fmt::format("{}.k_n={}", w.stiffness_key, k), fmt::format("{}.k_s={}", w.stiffness_key, k)});
  const double mid = w.impulse_dt[w.impulse_dt.size() / 2];
  for (const std::string eng : {"box2d", "bullet", "ode"}) {
    const std::string base = eng == "ode" ? "ode quick-step" : eng;
    for (double dt : w.impulse_dt) {
      std::vector<std::string> sets{fmt::format("accuracy.dt={}", dt)};
      if (eng == "ode") sets.push_back("accuracy.stepper=\"quick\"");
      add(eng, base, "dt", dt, sets);
      if (eng == "ode" && w.ode_direct)
        add(eng, "ode step", "dt", dt, {fmt::format("accuracy.dt={}", dt), "accuracy.stepper=\"step\""});
    }
    if (quick) continue;
    for (int it : {2, 4, 16, 32}) {
      std::vector<std::string> sets{fmt::format("accuracy.dt={}", mid),
                                    fmt::format("accuracy.velocity_iterations={}", it)};
      if (eng == "ode") sets.push_back("accuracy.stepper=\"quick\"");
      add(eng, base + ", iterations", "iterations", it, sets);
    }
    if (eng == "bullet")
      for (int sub : {2, 4, 8})
        add(eng, "bullet, sub-steps", "substeps", sub,
            {fmt::format("accuracy.dt={}", w.impulse_dt.front()), fmt::format("accuracy.substeps={}", sub)});
  }
  return out;
}

// Scene texts. Every scene is 2-D, so all four engines run it; gravity is tilted for the inclines.
std::string header(double duration, double gx, double gy, const std::string& effects,
                   const std::string& material) {
  return fmt::format(R"toml(
[scene]
duration = {d}
gravity = [{gx:.17g}, {gy:.17g}]
effects = [{effects}]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
{material}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
)toml",
                     fmt::arg("d", duration), fmt::arg("gx", gx), fmt::arg("gy", gy),
                     fmt::arg("effects", effects), fmt::arg("material", material));
}

// A scene's fixed parts; measure, reference and settings are filled in by each scene.
CostScene scene_head(std::string name, std::string description, std::string reference_note) {
  CostScene s;
  s.name = std::move(name), s.description = std::move(description),
  s.reference_note = std::move(reference_note);
  return s;
}

CostMeasurement exactly(double v) {
  CostMeasurement m;
  m.value = v;
  return m;
}

CostScene pair_restitution(bool quick) {
  // Table 2.1's pair: r = 1, density 2, k_n = 5e6, eps 0.7, head-on at 50 cm/s each. Contact 2.5 ms.
  const std::string toml = R"toml(
[scene]
duration = 0.02
effects = ["normal_contact"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 5e6
restitution = 0.7
[[bodies]]
radius = 1.0
density = 2.0
position = [-1.05, 0.0]
velocity = [50.0, 0.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [1.05, 0.0]
velocity = [-50.0, 0.0]
)toml";
  CostScene s =
      scene_head("pair-restitution",
                 "two discs head-on (Table 2.1: r = 1 cm, k_n = 5e6 dyn/cm, restitution 0.7, 50 cm/s each)",
                 "eq. 2.2: the restitution the material asks for, 0.7");
  s.reference = [] { return exactly(0.7); };
  s.measure = [toml](const CostSetting& c) {
    CostMeasurement m;
    auto e = run(c, toml, 0.02, m);
    const Frame f = e->frame();
    m.value = (f.velocity[3] - f.velocity[0]) / 100.0;
    return m;
  };
  Sweep w{
      {5e-4, 2.5e-4, 1e-4, 5e-5, 2.5e-5, 1e-5, 5e-6}, {0.05, 0.02, 0.005, 1e-3, 1e-4}, {}, {}, 2.5e-4, ""};
  w.impulse_dt = {2e-3, 1e-3, 5e-4, 2e-4, 1e-4};
  if (quick)
    w.native_dt = {5e-4, 1e-4, 2.5e-5}, w.tolerance = {0.05, 0.005, 1e-4}, w.impulse_dt = {2e-3, 5e-4, 1e-4};
  s.settings = settings_for(w, quick);
  return s;
}

CostScene bounce_apex(bool quick) {
  // A disc dropped 10 cm onto the floor, restitution 0.8: the rigid apex after the bounce is 1 + 0.64 x 10
  // cm. A soft contact lasting t_c loses about g t_c / v of that (stiffness is a modelling choice).
  const std::string toml =
      header(1.7, 0, -kG, "\"gravity\", \"normal_contact\"", "k_n = 1e9\nrestitution = 0.8") +
      R"toml(
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 11.0]
)toml";
  CostScene s = scene_head(
      "bounce-apex",
      "a disc dropped 10 cm onto a floor (restitution 0.8, native k_n = 1e9 dyn/cm): height of the first "
      "apex after the bounce",
      "rigid bounce: apex = 1 + 0.8^2 x 10 = 7.4 cm");
  s.reference = [] { return exactly(1 + 0.64 * 10); };
  s.measure = [toml](const CostSetting& c) {
    CostMeasurement m;
    double apex = 0;
    bool bounced = false;
    run(
        c, toml, 1.7, m,
        [&](const Engine& e) {
          const Frame f = e.frame();
          bounced |= f.velocity[1] > 0;
          if (bounced) apex = std::max(apex, f.position[1]);
        },
        1e-4);
    m.value = apex;
    return m;
  };
  Sweep w{{1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6},
          {0.05, 0.01, 0.002, 5e-4, 1e-4},
          {1e7, 1e8, 1e9, 1e10},
          {5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4},
          2.5e-5,
          "materials.m"};
  if (quick)
    w.native_dt = {1e-4, 1e-5, 2e-6}, w.tolerance = {0.05, 0.002, 1e-4}, w.impulse_dt = {5e-3, 1e-3, 2e-4};
  s.settings = settings_for(w, quick);
  return s;
}

// A body on an incline (gravity tilted by `angle_deg`, the floor y = 0) whose downslope distance after
// `duration` has an analytic value; the sweep is the same for both such scenes.
CostScene incline_scene(bool quick, std::string name, std::string description, const std::string& body,
                        double angle_deg, double mu, double duration, double exact,
                        const std::string& formula) {
  const double th = angle_deg * M_PI / 180;
  const std::string toml =
      header(duration, kG * std::sin(th), -kG * std::cos(th),
             "\"gravity\", \"normal_contact\", \"friction\", \"rotation\"",
             fmt::format("k_n = 1e8\nrestitution = 0.3\nk_s = 1e8\ndamping_s = 3e4\nmu = {}", mu)) +
      body;
  CostScene s =
      scene_head(std::move(name), std::move(description), fmt::format("{} = {:.3f} cm", formula, exact));
  s.reference = [exact] { return exactly(exact); };
  s.measure = [toml, duration](const CostSetting& c) {
    CostMeasurement m;
    auto e = run(c, toml, duration, m);
    m.value = e->frame().position[0];
    return m;
  };
  // k_n = 1e8 on 8 g: contacts of 0.9 ms, so the predictor-corrector's largest step is 1e-4 s.
  Sweep w{{1e-4, 5e-5, 2e-5, 1e-5, 5e-6},
          {0.05, 0.01, 0.002, 5e-4},
          {1e6, 1e7, 1e8, 1e9},
          {5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4},
          1e-4,
          "materials.m"};
  if (quick) w.native_dt = {1e-4, 2e-5, 5e-6}, w.tolerance = {0.05, 0.002}, w.impulse_dt = {5e-3, 1e-3, 2e-4};
  s.settings = settings_for(w, quick);
  return s;
}

CostScene slide_to_rest(bool quick) {
  // A 2 x 2 cm block sliding down a 20 deg incline at 100 cm/s with mu 0.6 stops after
  // v0^2 / (2 g (mu cos - sin)) = 22.98 cm.
  const double th = 20 * M_PI / 180, mu = 0.6, v0 = 100;
  return incline_scene(quick, "slide-to-rest",
                       "a 2 x 2 cm block sliding at 100 cm/s down a 20 deg incline, mu 0.6: distance to rest",
                       R"toml(
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [0.0, 1.0]
velocity = [100.0, 0.0]
)toml",
                       20, mu, 1.0, v0 * v0 / (2 * kG * (mu * std::cos(th) - std::sin(th))),
                       "v0^2 / (2 g (mu cos th - sin th))");
}

CostScene rolling_disc(bool quick) {
  // A disc rolling from rest down a 30 deg incline without slipping: x(t) = g sin(th) t^2 / 3.
  const double th = 30 * M_PI / 180, t = 0.5;
  return incline_scene(quick, "rolling-disc",
                       "a disc rolling from rest down a 30 deg incline (mu 1): distance after 0.5 s",
                       R"toml(
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 1.0]
)toml",
                       30, 1.0, t, kG * std::sin(th) * t * t / 3, "g sin(th) t^2 / 3");
}

CostScene loaded_die(bool quick) {
  // p_h of the 2-D die at f = 0.3, eps = 0.7 (the loaded-die suite's throws); reference: the finest
  // native run.
  const std::size_t throws = quick ? 150 : 2401;
  const Die2d die{0.3, 0.7, 0.8};
  auto p_h = [die, throws](const std::string& engine, const std::vector<std::string>& sets,
                           CostMeasurement& m) {
    const auto rows = run_ensemble(throws, 1, [&](std::size_t i) {
      return std::vector<double>{double(throw_die_2d(engine, die, 1987, i, sets).face_down)};
    });
    std::size_t hi = 0, captured = 0;
    for (const auto& r : rows)
      if (r[0] >= 0) ++captured, hi += (r[0] == 1 || r[0] == 2);
    const Proportion p = wilson_interval(hi, captured);
    m.value = p.p, m.half_width = p.half_width();
  };
  CostScene s = scene_head(
      "loaded-die",
      fmt::format("the 2-D loaded die at f = 0.3, eps = 0.7: p_h from {} throws (error with its 95 % "
                  "interval, absolute)",
                  throws),
      "the finest native run (Verlet, dt = 5e-6 s), with its own interval");
  s.statistical = true;
  s.measure = [p_h](const CostSetting& c) {
    CostMeasurement m;
    p_h(c.engine, c.sets, m);
    return m;
  };
  s.reference = [p_h] {
    CostMeasurement m;
    p_h("native", {"accuracy.dt=5e-6"}, m);
    return m;
  };
  Sweep w{{1e-4, 5e-5, 2e-5, 1e-5}, {0.05, 0.01, 0.002}, {}, {2e-3, 1e-3, 5e-4, 2e-4}, 1e-4, ""};
  if (quick) w.native_dt = {1e-4, 2e-5}, w.tolerance = {0.01}, w.impulse_dt = {2e-3, 5e-4};
  s.settings = settings_for(w, quick);
  return s;
}

// A bed of `count` discs (radii uniform in [0.4, 0.6] cm, density 2) poured into a box 40 cm wide from
// a loose seeded grid and left to settle for `duration`: each engine pours its own bed.
std::string bed_scene(int count, double duration) {
  std::string toml = fmt::format(R"toml(
[scene]
duration = {d}
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-4
[materials.m]
k_n = 1e6
restitution = 0.5
k_s = 1e6
mu = 0.5
[[walls]]
from = [0.0, 0.0]
to = [40.0, 0.0]
[[walls]]
from = [0.0, 200.0]
to = [0.0, 0.0]
[[walls]]
from = [40.0, 0.0]
to = [40.0, 200.0]
)toml",
                                 fmt::arg("d", duration));
  Rng rng(2026);
  const int per_row = 30;  // 1.3 cm apart: no two discs touch at the start
  for (int k = 0; k < count; ++k)
    toml += fmt::format(
        "[[bodies]]\nradius = {:.6f}\ndensity = 2.0\nposition = [{:.4f}, {:.4f}]\nvelocity = [{:.4f}, 0.0]\n",
        rng.uniform(0.4, 0.6), 1.15 + 1.3 * (k % per_row) + 0.1 * (k / per_row % 2),
        1.0 + 1.3 * (k / per_row), rng.uniform(-5, 5));
  return toml;
}

// Settled height (mean top of the highest 5 % of discs), packing fraction below it, and mean contacts
// per disc (gaps under 2 % of the smaller radius count: the impulse engines keep a skin).
CostMeasurement bed_state(const Frame& f, CostMeasurement m) {
  const std::size_t n = f.radius.size();
  std::vector<double> tops;
  double area = 0;
  for (std::size_t i = 0; i < n; ++i)
    tops.push_back(f.position[3 * i + 1] + f.radius[i]), area += M_PI * f.radius[i] * f.radius[i];
  std::sort(tops.begin(), tops.end(), std::greater<>());
  const std::size_t top = std::max<std::size_t>(1, n / 20);
  double height = 0;
  for (std::size_t k = 0; k < top; ++k) height += tops[k] / top;
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = f.position[3 * i] - f.position[3 * j],
                   dy = f.position[3 * i + 1] - f.position[3 * j + 1];
      const double gap = std::hypot(dx, dy) - f.radius[i] - f.radius[j];
      contacts += gap < 0.02 * std::min(f.radius[i], f.radius[j]);
    }
  m.value = height;
  m.extra = {area / (40.0 * height), 2.0 * contacts / n, double(n)};  // the last: particles, for the cost
  m.detail =
      fmt::format("height {:.3f} cm, packing {:.4f}, coordination {:.3f}", height, m.extra[0], m.extra[1]);
  return m;
}

CostScene poured_bed(bool quick) {
  const int count = quick ? 150 : 1000;
  const double duration = quick ? 1.0 : 2.0;
  const std::string toml = bed_scene(count, duration);
  CostScene s = scene_head(
      "poured-bed",
      fmt::format("{} discs (r 0.4-0.6 cm) poured into a 40 cm box and settled for {} s; error: the "
                  "largest relative error of settled height, packing fraction and coordination number",
                  count, duration),
      "the finest native run (Verlet, dt = 1e-5 s)");
  s.expensive = true;
  s.measure = [toml, duration](const CostSetting& c) {
    CostMeasurement m;
    auto e = run(c, toml, duration, m);
    return bed_state(e->frame(), m);
  };
  s.reference = [toml, duration] {
    CostMeasurement m;
    const CostSetting finest{"native", "native verlet", "dt", 1e-5, {"accuracy.dt=1e-5"}};
    auto e = run(finest, toml, duration, m);
    return bed_state(e->frame(), m);
  };
  s.error = [](const CostMeasurement& m, const CostMeasurement& ref) {
    double worst = std::abs(m.value - ref.value) / ref.value;
    for (std::size_t k = 0; k < 2; ++k)
      worst = std::max(worst, std::abs(m.extra[k] - ref.extra[k]) / ref.extra[k]);
    return worst;
  };
  // k_n = 1e6 on 1.6 g: contacts of 2.8 ms.
  Sweep w{{2e-4, 1e-4, 5e-5, 2e-5}, {0.05, 0.01, 0.002}, {}, {2e-3, 1e-3, 5e-4, 2e-4}, 3e-4, ""};
  if (quick) w.native_dt = {2e-4, 5e-5}, w.tolerance = {0.01}, w.impulse_dt = {2e-3, 5e-4};
  w.ode_direct = false;
  s.settings = settings_for(w, quick);
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

std::vector<CostScene> cost_scenes(bool quick) {
  return {pair_restitution(quick), bounce_apex(quick), slide_to_rest(quick),
          rolling_disc(quick),     loaded_die(quick),  poured_bed(quick)};
}

std::vector<CostRow> run_cost_study(const CostOptions& o) {
  std::vector<CostScene> scenes = cost_scenes(o.quick);
  std::vector<CostRow> rows;
  for (CostScene& sc : scenes) {
    if (!o.scenes.empty() && std::find(o.scenes.begin(), o.scenes.end(), sc.name) == o.scenes.end()) continue;
    if (std::optional<std::vector<CostRow>> taken = o.taken ? o.taken(sc.name) : std::nullopt) {
      if (o.log)
        o.log(fmt::format("{}: {} settings taken from the interrupted study", sc.name, taken->size()));
      rows.insert(rows.end(), taken->begin(), taken->end());
      continue;
    }
    const std::size_t first_row = rows.size();
    const CostMeasurement reference = sc.reference();
    const double ref = reference.value;
    if (o.log) o.log(fmt::format("{}: reference {:.6g} ({})", sc.name, ref, sc.reference_note));
    for (const CostSetting& c : sc.settings) {
      CostMeasurement m;
      std::vector<double> seconds;
      std::string failure;
      const int repeats = sc.statistical || sc.expensive ? 1 : std::max(1, o.repeats);
      for (int k = 0; k < repeats && failure.empty(); ++k) {
        const auto start = std::chrono::steady_clock::now();
        try {
          m = sc.measure(c);
        } catch (const std::exception& ex) {
          failure = ex.what();  // a setting that cannot run is a result too
        }
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      CostRow r{sc.name, c.engine,        c.method, c.knob,     c.value,      m.value, 0,
                0,       median(seconds), m.steps,  m.rejected, m.iterations, failure, m.detail};
      if (!failure.empty()) {
        r.error = NAN;
      } else if (sc.error) {
        r.error = sc.error(m, reference);
        if (m.extra.size() == 3 && r.steps > 0)  // the bed: what one particle-step cost
          r.detail += fmt::format(", {:.3g} us per particle-step", 1e6 * r.seconds / (r.steps * m.extra[2]));
      } else if (sc.statistical) {
        r.error = std::abs(m.value - ref);
        r.error_half_width = std::hypot(m.half_width, reference.half_width);
      } else {
        r.error = std::abs(m.value - ref) / std::abs(ref);
      }
      if (o.log)
        o.log(failure.empty()
                  ? fmt::format("  {} {} = {:g}: {:.6g} (error {:.2e}), {:.4f} s, {:.0f} steps", c.method,
                                c.knob, c.value, m.value, r.error, r.seconds, r.steps)
                  : fmt::format("  {} {} = {:g}: failed: {}", c.method, c.knob, c.value, failure));
      rows.push_back(r);
    }
    if (o.finished)
      o.finished(sc.name, std::vector<CostRow>(rows.begin() + static_cast<long>(first_row), rows.end()));
  }
  return rows;
}

nlohmann::json cost_row_json(const CostRow& r, bool exact) {
  auto number = [exact](double v) { return exact ? exact_json(v) : nlohmann::json(v); };  // (dumped as null)
  return {{"scene", r.scene},
          {"failure", r.failure},
          {"engine", r.engine},
          {"method", r.method},
          {"knob", r.knob},
          {"value", number(r.value)},
          {"measured", number(r.measured)},
          {"error", number(r.error)},
          {"error_half_width", number(r.error_half_width)},
          {"seconds", number(r.seconds)},
          {"steps", number(r.steps)},
          {"rejected_steps", number(r.rejected)},
          {"solver_iterations", number(r.iterations)},
          {"detail", r.detail}};
}

CostRow cost_row_from_json(const nlohmann::json& j) {
  auto number = [&](const char* key) { return from_exact_json(j.at(key)); };
  try {
    CostRow r;
    r.scene = j.at("scene"), r.failure = j.at("failure"), r.engine = j.at("engine");
    r.method = j.at("method"), r.knob = j.at("knob"), r.detail = j.at("detail");
    r.value = number("value"), r.measured = number("measured"), r.error = number("error");
    r.error_half_width = number("error_half_width"), r.seconds = number("seconds"), r.steps = number("steps");
    r.rejected = number("rejected_steps"), r.iterations = number("solver_iterations");
    return r;
  } catch (const std::exception& e) {  // (nlohmann's, or from_exact_json's)
    throw std::runtime_error(std::string("cost row: ") + e.what());
  }
}

const CostRow* cheapest_reaching(const std::vector<CostRow>& rows, const std::string& scene,
                                 const std::string& method, double target) {
  const CostRow* best = nullptr;
  for (const CostRow& r : rows)
    if (r.scene == scene && r.method == method && r.error <= target && (!best || r.seconds < best->seconds))
      best = &r;
  return best;
}

void write_cost_report(const std::vector<CostRow>& rows, const std::vector<CostScene>& scenes,
                       const std::string& dir, bool quick) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  nlohmann::json j = nlohmann::json::array();
  for (const CostRow& r : rows) j.push_back(cost_row_json(r));
  write_file_atomically((fs::path(dir) / "cost.json").string(), j.dump(1) + "\n");

  Report plots;  // collects the plots
  std::string md = fmt::format(
      "# What accuracy costs ({} mode)\n\nMade by `grainlab cost{} --out {}`. Error: relative to the "
      "reference, "
      "except the loaded die's p_h (absolute, with its 95 % interval). Seconds: median wall time of repeated "
      "runs. Solver iterations: force evaluations (native) or steps x iterations (impulse engines; ODE's "
      "direct stepper has none).\n\n",
      quick ? "quick" : "full", quick ? " --quick" : "", dir);
  for (const CostScene& sc : scenes) {
    std::vector<std::string> methods;
    for (const CostRow& r : rows)
      if (r.scene == sc.name && std::find(methods.begin(), methods.end(), r.method) == methods.end())
        methods.push_back(r.method);
    if (methods.empty()) continue;
    md += fmt::format("## {}\n\n{}. Reference: {}.\n\n", sc.name, sc.description, sc.reference_note);
    PlotSpec plot{"cost_" + sc.name + ".png",
                  sc.name + ": error against cost",
                  "wall time per run (s)",
                  "error",
                  true,
                  {}};
    plot.logy = true;
    md += "| curve | error 1e-1 | error 1e-2 | error 1e-3 |\n|---|---|---|---|\n";
    for (const std::string& method : methods) {
      PlotSpec::Series s{method, "linepoints", {}, {}, {}};
      md += "| " + method + " |";
      for (double target : {1e-1, 1e-2, 1e-3}) {
        const CostRow* r = cheapest_reaching(rows, sc.name, method, target);
        md += r ? fmt::format(" {} = {:g}: {:.2g} s |", r->knob, r->value, r->seconds)
                : std::string(" not reached |");
      }
      md += "\n";
      for (const CostRow& r : rows)
        if (r.scene == sc.name && r.method == method && r.failure.empty()) {
          s.x.push_back(std::max(r.seconds, 1e-7));
          s.y.push_back(std::max(r.error, 1e-12));  // exact results sit on the plot's floor
        }
      plot.series.push_back(s);
    }
    md +=
        "\n| curve | setting | measured | error | seconds | steps | rejected | solver iterations |\n"
        "|---|---|---|---|---|---|---|---|\n";
    for (const CostRow& r : rows)
      if (r.scene == sc.name && !r.failure.empty())
        md += fmt::format("| {} | {} = {:g} | failed: {} | - | {:.3g} | - | - | - |\n", r.method, r.knob,
                          r.value, r.failure, r.seconds);
      else if (r.scene == sc.name)
        // An ensemble's step counts are not collected (each throw is its own engine).
        md += fmt::format("| {} | {} = {:g} | {:.6g} | {:.2e}{} | {:.3g} | {} |\n", r.method, r.knob, r.value,
                          r.measured, r.error,
                          sc.statistical ? fmt::format(" +- {:.2e}", r.error_half_width)
                                         : (r.detail.empty() ? std::string() : " (" + r.detail + ")"),
                          r.seconds,
                          sc.statistical
                              ? std::string("- | - | -")
                              : fmt::format("{:.0f} | {:.0f} | {:.0f}", r.steps, r.rejected, r.iterations));
    md += fmt::format("\n![{}]({})\n\n", sc.name, plot.file);
    plots.plots.push_back(plot);
  }
  write_file_atomically((fs::path(dir) / "cost.md").string(), md);
  write_plots(plots.plots, dir);
}

}  // namespace grainlab::validation
