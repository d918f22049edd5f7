// Building, measuring, saving and loading the Ch. III impact beds.
#include "impact_bed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "engine.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"
#include "rng.hpp"

namespace grainlab::validation {

namespace {

constexpr const char* kBedTag = "# grainlab-bed:";

// The deposition stiffness: 100 x softer than the bed's, so the pour takes 10 x fewer steps. The weight of
// the whole column then overlaps the bottom contact by ~1e-3 r, and the stiff bed relaxes from there.
constexpr double kSoftening = 100;
// Restitution while pouring: lower than the bed's so the pour comes to rest in about a second.
constexpr double kPourRestitution = 0.3;

std::string walls_toml(const BedSpec& s, double wall_height) {
  if (s.periodic) return "[[walls]]\ntype = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n";
  return fmt::format(
      "[[walls]]\nfrom = [0.0, 0.0]\nto = [{w:.17g}, 0.0]\n"
      "[[walls]]\nfrom = [0.0, {h:.17g}]\nto = [0.0, 0.0]\n"
      "[[walls]]\nfrom = [{w:.17g}, 0.0]\nto = [{w:.17g}, {h:.17g}]\n",
      fmt::arg("w", s.width), fmt::arg("h", wall_height));
}

std::string header_toml(const BedSpec& s, const std::string& name, double duration, double k_n,
                        double restitution, double mu, double wall_height) {
  const double m = s.density * M_PI * s.radius * s.radius;
  return fmt::format(
      "{tag} preparation={prep} seed={seed} count={n} width={w:.17g} height={h:.17g} periodic={per} "
      "radius={r:.17g} density={rho:.17g} k_n={k:.17g} restitution={e:.17g} mu={mu:.17g} "
      "levelled={lev}\n"
      "[scene]\nname = \"{name}\"\nduration = {d:.17g}\nseed = {seed}\n{periodic}"
      "effects = [\"gravity\", \"normal_contact\", \"friction\", \"rotation\"]\n"
      "[accuracy]\nintegrator = \"verlet\"\ndt = {dt:.17g}\n"
      "[materials.sand]\nk_n = {kn:.17g}\nrestitution = {en:.17g}\nk_s = {kn:.17g}\nmu = {mun:.17g}\n{walls}",
      fmt::arg("tag", kBedTag), fmt::arg("prep", s.preparation), fmt::arg("seed", s.seed),
      fmt::arg("n", s.count), fmt::arg("w", s.width), fmt::arg("h", s.height),
      fmt::arg("per", s.periodic ? "true" : "false"), fmt::arg("r", s.radius), fmt::arg("rho", s.density),
      fmt::arg("k", s.k_n), fmt::arg("e", s.restitution), fmt::arg("mu", s.mu),
      fmt::arg("lev", s.levelled ? "true" : "false"), fmt::arg("name", name), fmt::arg("d", duration),
      fmt::arg("periodic", s.periodic ? fmt::format("periodic_x = [0.0, {:.17g}]\n", s.width) : ""),
      fmt::arg("dt", contact_time(k_n, m, m) / 30), fmt::arg("kn", k_n), fmt::arg("en", restitution),
      fmt::arg("mun", mu), fmt::arg("walls", walls_toml(s, wall_height)));
}

std::string bodies_toml(const std::vector<BodySpec>& bodies, double density) {
  std::string out;
  for (const BodySpec& b : bodies)
    out += fmt::format(
        "[[bodies]]\nid = {}\nradius = {:.17g}\ndensity = {:.17g}\nposition = [{:.17g}, {:.17g}]\n"
        "velocity = [{:.17g}, {:.17g}]\nangle = {:.17g}\nspin = {:.17g}\n",
        b.id, b.radius, density, b.position.x, b.position.y, b.velocity.x, b.velocity.y, b.angle, b.spin);
  return out;
}

// Random sequential placement in a tall column above the box: a sparse "rain" (area fraction 0.25) that
// falls together, so the bed's structure comes from the deposition, not from a lattice.
std::vector<BodySpec> rain(const BedSpec& s, Rng& rng, double& column_top) {
  const double r = s.radius, m = s.density * M_PI * r * r;
  const double lo = s.periodic ? 0.0 : r * 1.05, hi = s.periodic ? s.width : s.width - r * 1.05;
  const double column = s.count * M_PI * r * r / (0.25 * (hi - lo));
  column_top = column + 2 * r;
  std::vector<BodySpec> out;
  const double cell = 2 * r;
  const int nx = std::max(1, static_cast<int>(s.width / cell)), ny = static_cast<int>(column / cell) + 2;
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(nx * ny));
  auto cell_of = [&](double x, double y) {
    const int cx = std::clamp(static_cast<int>(x / cell), 0, nx - 1);
    const int cy = std::clamp(static_cast<int>((y - r) / cell), 0, ny - 1);
    return std::pair{cx, cy};
  };
  while (static_cast<int>(out.size()) < s.count) {
    const double x = rng.uniform(lo, hi), y = r * 1.05 + rng.uniform(0, column);
    const auto [cx, cy] = cell_of(x, y);
    bool free = true;
    for (int i = cx - 1; i <= cx + 1 && free; ++i)
      for (int j = cy - 1; j <= cy + 1 && free; ++j) {
        const int ii = s.periodic ? (i + nx) % nx : i;
        if (ii < 0 || ii >= nx || j < 0 || j >= ny) continue;
        for (std::size_t k : grid[static_cast<std::size_t>(ii + nx * j)]) {
          double dx = out[k].position.x - x;
          if (s.periodic) dx -= s.width * std::round(dx / s.width);
          if (std::hypot(dx, out[k].position.y - y) < 2.1 * r) free = false;
        }
      }
    if (!free) continue;
    BodySpec b;
    b.id = static_cast<std::int64_t>(out.size());
    b.radius = r, b.mass = m, b.inertia = 0.5 * m * r * r;
    b.position = {x, y};
    b.velocity = {rng.uniform(-20, 20), rng.uniform(-20, 0)};
    grid[static_cast<std::size_t>(cx + nx * cy)].push_back(out.size());
    out.push_back(b);
  }
  return out;
}

std::vector<BodySpec> bodies_from(const Frame& f, double mass_density) {
  std::vector<BodySpec> out;
  for (std::size_t i = 0; i < f.id.size(); ++i) {
    BodySpec b;
    b.id = f.id[i];
    b.radius = f.radius[i];
    b.mass = mass_density * M_PI * b.radius * b.radius;
    b.inertia = 0.5 * b.mass * b.radius * b.radius;
    b.position = {f.position[3 * i], f.position[3 * i + 1]};
    b.velocity = {f.velocity[3 * i], f.velocity[3 * i + 1]};
    b.angle = f.angle[i];
    b.spin = f.spin[i];
    out.push_back(b);
  }
  return out;
}

double kinetic(const std::vector<BodySpec>& bodies) {
  double e = 0;
  for (const BodySpec& b : bodies)
    e += 0.5 * b.mass * (b.velocity.x * b.velocity.x + b.velocity.y * b.velocity.y) +
         0.5 * b.inertia * b.spin * b.spin;
  return e;
}

// Runs `toml` on the native engine for its duration and returns the discs where they end.
std::vector<BodySpec> settle(const std::string& toml, double density) {
  const Scene scene = parse_scene(toml, "<bed>");
  auto engine = make_engine("native", scene);
  engine->advance_to(scene.duration);
  return bodies_from(engine->frame(), density);
}

BedSpec parse_tag(const std::string& text, const std::string& path) {
  const auto at = text.find(kBedTag);
  if (at == std::string::npos)
    throw InputError({path, 0}, "scene_text", "is not a grainlab bed (its scene has no bed description)");
  std::istringstream line(
      text.substr(at + std::string(kBedTag).size(), text.find('\n', at) - at - std::string(kBedTag).size()));
  BedSpec s;
  std::string item;
  while (line >> item) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) continue;
    const std::string k = item.substr(0, eq), v = item.substr(eq + 1);
    try {
      if (k == "preparation")
        s.preparation = v;
      else if (k == "seed")
        s.seed = std::stoull(v);
      else if (k == "count")
        s.count = std::stoi(v);
      else if (k == "width")
        s.width = std::stod(v);
      else if (k == "height")
        s.height = std::stod(v);
      else if (k == "periodic")
        s.periodic = v == "true";
      else if (k == "radius")
        s.radius = std::stod(v);
      else if (k == "density")
        s.density = std::stod(v);
      else if (k == "k_n")
        s.k_n = std::stod(v);
      else if (k == "restitution")
        s.restitution = std::stod(v);
      else if (k == "mu")
        s.mu = std::stod(v);
      else if (k == "levelled")
        s.levelled = v == "true";
    } catch (const std::exception&) {
      throw InputError({path, 0}, "scene_text",
                       fmt::format("bed description: {} is not a valid value", item));
    }
  }
  return s;
}

}  // namespace

BedSurface bed_surface(const std::vector<BodySpec>& bodies, double xmin, double xmax) {
  BedSurface s;
  s.type.assign(bodies.size(), 0);
  if (bodies.empty()) return s;
  // The surface profile on a fine grid: the highest disc point above each x, and which disc it is.
  const double dx = 0.05 * bodies.front().radius;
  const int n = std::max(2, static_cast<int>((xmax - xmin) / dx));
  std::vector<double> h(static_cast<std::size_t>(n), -1e300);
  std::vector<long> who(static_cast<std::size_t>(n), -1);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double r = bodies[i].radius, xc = bodies[i].position.x, yc = bodies[i].position.y;
    const int a = std::max(0, static_cast<int>((xc - r - xmin) / dx)),
              b = std::min(n - 1, static_cast<int>((xc + r - xmin) / dx) + 1);
    for (int k = a; k <= b; ++k) {
      const double x = xmin + (k + 0.5) * dx, u = r * r - (x - xc) * (x - xc);
      if (u < 0) continue;
      const double y = yc + std::sqrt(u);
      if (y > h[static_cast<std::size_t>(k)])
        h[static_cast<std::size_t>(k)] = y, who[static_cast<std::size_t>(k)] = static_cast<long>(i);
    }
  }
  // Exposed: the highest disc over at least half a radius of x. A deeper disc glimpsed through the
  // narrow gap between two surface discs is not a surface grain (it would fake a brink).
  std::vector<int> share(bodies.size(), 0);
  for (int k = 0; k < n; ++k)
    if (who[static_cast<std::size_t>(k)] >= 0)
      ++share[static_cast<std::size_t>(who[static_cast<std::size_t>(k)])];
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (share[i] * dx >= 0.5 * bodies[i].radius) s.grains.push_back(i);
  std::sort(s.grains.begin(), s.grains.end(),
            [&](std::size_t a, std::size_t b) { return bodies[a].position.x < bodies[b].position.x; });
  for (std::size_t i : s.grains) s.type[i] = 1;
  const double lo = xmin + 0.1 * (xmax - xmin), hi = xmax - 0.1 * (xmax - xmin);
  double top = -1e300, sum = 0, sum2 = 0;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const double x = xmin + (k + 0.5) * dx;
    if (x >= lo && x <= hi) top = std::max(top, h[static_cast<std::size_t>(k)]);
  }
  for (std::size_t i : s.grains) {
    const double x = bodies[i].position.x;
    if (x < lo || x > hi) continue;
    const double t = bodies[i].position.y + bodies[i].radius;
    sum += t, sum2 += t * t, ++m;
  }
  s.top = top;
  s.roughness = m > 1 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / m) / (m - 1))) : 0;
  // Steps between consecutive exposed grains.
  for (std::size_t k = 0; k + 1 < s.grains.size(); ++k) {
    const BodySpec &a = bodies[s.grains[k]], &b = bodies[s.grains[k + 1]];
    const double step = b.position.y - a.position.y, r = std::min(a.radius, b.radius);
    if (step <= -r) {
      ++s.brinks;
      s.type[s.grains[k]] = 2;
      if (k > 0) s.type[s.grains[k - 1]] = 2;
    } else if (step >= r) {
      ++s.anti_brinks;
      s.type[s.grains[k + 1]] = 3;
      if (k + 2 < s.grains.size()) s.type[s.grains[k + 2]] = 3;
    }
  }
  return s;
}

std::string bed_scene_text(const BedSpec& spec, const std::vector<BodySpec>& bodies, double duration) {
  return header_toml(spec, fmt::format("{} impact bed (seed {})", spec.preparation, spec.seed), duration,
                     spec.k_n, spec.restitution, spec.mu, spec.height) +
         bodies_toml(bodies, spec.density);
}

BedStats measure_bed(const Scene& scene, const BedSpec& spec) {
  BedStats st;
  const auto& b = scene.bodies;
  const BedSurface surf = bed_surface(b, 0, spec.width);
  st.top = surf.top, st.roughness = surf.roughness;
  st.brinks = surf.brinks, st.anti_brinks = surf.anti_brinks;
  // Packing in the interior: 2 diameters from the side walls (none when periodic), the floor and the top.
  const double d = 2 * spec.radius;
  const double x0 = spec.periodic ? 0 : 2 * d, x1 = spec.periodic ? spec.width : spec.width - 2 * d;
  const double y0 = 2 * d, y1 = surf.top - 2 * d;
  double area = 0;
  for (const BodySpec& p : b) {
    // Area of the disc inside the window, on a 40 x 40 sub-grid of its bounding box (exact enough).
    const int q = 40;
    int inside = 0, total = 0;
    for (int i = 0; i < q; ++i)
      for (int j = 0; j < q; ++j) {
        const double u = -1 + (2 * i + 1.0) / q, v = -1 + (2 * j + 1.0) / q;
        if (u * u + v * v > 1) continue;
        ++total;
        const double x = p.position.x + u * p.radius, y = p.position.y + v * p.radius;
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) ++inside;
      }
    area += M_PI * p.radius * p.radius * inside / std::max(1, total);
  }
  st.packing_fraction = (x1 > x0 && y1 > y0) ? area / ((x1 - x0) * (y1 - y0)) : 0;
  // Contacts: overlapping pairs (a settled bed overlaps by ~1e-5 r) and discs touching a wall.
  std::size_t contacts2 = 0;
  const double tol = 1e-4 * spec.radius;  // settled overlaps are ~1e-6 r; a gap this small is a contact
  for (std::size_t i = 0; i < b.size(); ++i) {
    for (std::size_t j = i + 1; j < b.size(); ++j) {
      double dx = b[i].position.x - b[j].position.x;
      if (spec.periodic) dx -= spec.width * std::round(dx / spec.width);
      if (std::hypot(dx, b[i].position.y - b[j].position.y) < b[i].radius + b[j].radius + tol) contacts2 += 2;
    }
    if (b[i].position.y - b[i].radius < tol) ++contacts2;
    if (!spec.periodic &&
        (b[i].position.x - b[i].radius < tol || spec.width - b[i].position.x - b[i].radius < tol))
      ++contacts2;
  }
  st.coordination = b.empty() ? 0 : static_cast<double>(contacts2) / b.size();
  return st;
}

void check_preparation(const std::string& preparation, const std::string& key) {
  if (preparation != "loose" && preparation != "dense")
    throw InputError({key, 0}, preparation, "must be \"loose\" or \"dense\"");
}

Bed build_bed(const BedSpec& spec, const std::function<void(const std::string&)>& log) {
  check_preparation(spec.preparation, "--preparation");
  const auto start = std::chrono::steady_clock::now();
  Rng rng(spec.seed, 0);
  double column_top = 0;
  // A levelled bed is poured with 15 % more discs and scraped: the highest discs are taken away until
  // `count` remain, as an experimenter levels a sand bed with a straight edge.
  BedSpec pour_spec = spec;
  if (spec.levelled) pour_spec.count = static_cast<int>(std::ceil(spec.count * 1.15));
  std::vector<BodySpec> bodies = rain(pour_spec, rng, column_top);
  // Loose: the grains keep their friction while they pile up, and lock into an open packing. Dense: they
  // pour frictionless, slide into near close packing, and get their friction back once at rest.
  const double pour_mu = spec.preparation == "loose" ? spec.mu : 0.0;
  const double pour_time = std::sqrt(2 * column_top / 981.0) + 1.5;
  if (log)
    log(fmt::format("pouring {} discs ({} bed, seed {}, {:.2f} s simulated)", spec.count, spec.preparation,
                    spec.seed, pour_time));
  bodies = settle(header_toml(pour_spec, "pour", pour_time, spec.k_n / kSoftening, kPourRestitution, pour_mu,
                              column_top + 10) +
                      bodies_toml(bodies, spec.density),
                  spec.density);
  if (log) log(fmt::format("poured: kinetic energy {:.4g} erg", kinetic(bodies)));
  for (BodySpec& b : bodies) b.velocity = {}, b.spin = 0;
  if (spec.levelled) {
    std::stable_sort(bodies.begin(), bodies.end(),
                     [](const BodySpec& a, const BodySpec& b) { return a.position.y < b.position.y; });
    bodies.resize(static_cast<std::size_t>(spec.count));
    std::sort(bodies.begin(), bodies.end(), [](const BodySpec& a, const BodySpec& b) { return a.id < b.id; });
    for (std::size_t i = 0; i < bodies.size(); ++i) bodies[i].id = static_cast<std::int64_t>(i);
    if (log) log(fmt::format("levelled: the {} highest discs scraped off", pour_spec.count - spec.count));
    // Let the scraped surface settle before stiffening.
    bodies = settle(
        header_toml(spec, "settle", 0.3, spec.k_n / kSoftening, kPourRestitution, pour_mu, column_top + 10) +
            bodies_toml(bodies, spec.density),
        spec.density);
    for (BodySpec& b : bodies) b.velocity = {}, b.spin = 0;
  }
  // Stiffen in ten steps of 10^0.2, critically damped: each step releases only ~(10^0.2)^2 times the
  // new equilibrium's own elastic energy, so no grain is thrown (one jump to the bed's k_n would release
  // 100^2 times it and loosen the bed).
  if (log) log("stiffening to the bed's own k_n in 10 critically damped steps");
  for (int j = 1; j <= 10; ++j) {
    BedSpec step = spec;
    step.k_n = spec.k_n / kSoftening * std::pow(kSoftening, j / 10.0);
    step.restitution = 0;
    bodies = settle(bed_scene_text(step, bodies, 0.005), spec.density);
    for (BodySpec& b : bodies) b.velocity = {}, b.spin = 0;
  }
  // Then the bed's own material from rest, as every impact will start; 0.05 s is ~700 contact times.
  if (log) log("relaxing with the bed's own material (0.05 s)");
  bodies = settle(bed_scene_text(spec, bodies, 0.05), spec.density);
  Bed bed;
  bed.spec = spec;
  bed.stats.kinetic_energy = kinetic(bodies);
  for (BodySpec& b : bodies) b.velocity = {}, b.spin = 0;
  bed.scene = parse_scene(bed_scene_text(spec, bodies, 0.01), "<bed>");
  const double ke = bed.stats.kinetic_energy;
  bed.stats = measure_bed(bed.scene, spec);
  bed.stats.kinetic_energy = ke;
  bed.surface = bed_surface(bed.scene.bodies, 0, spec.width);
  bed.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bed.source = "built";
  return bed;
}

void write_bed(const Bed& bed, const std::string& path, bool overwrite) {
  auto engine = make_engine("native", bed.scene);
  RunOptions o;
  o.out = path;
  o.overwrite = overwrite;
  Scene s = bed.scene;
  s.output.frames = 2;
  run_scene(s, *engine, o);
}

Bed read_bed(const std::string& path) {
  const RunFileSummary f = read_run_file(path);
  const auto it = f.text.find("scene_text");
  if (it == f.text.end()) throw InputError({path, 0}, "scene_text", "is missing: not a grainlab run file");
  Bed bed;
  bed.spec = parse_tag(it->second, path);
  bed.scene = parse_scene(it->second, path);
  if (static_cast<int>(bed.scene.bodies.size()) != bed.spec.count)
    throw InputError({path, 0}, "scene_text",
                     fmt::format("lists {} discs but its bed description says {}", bed.scene.bodies.size(),
                                 bed.spec.count));
  bed.stats = measure_bed(bed.scene, bed.spec);
  bed.surface = bed_surface(bed.scene.bodies, 0, bed.spec.width);
  bed.source = path;
  return bed;
}

}  // namespace grainlab::validation
