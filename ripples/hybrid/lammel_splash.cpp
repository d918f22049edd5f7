#include "lammel_splash.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

namespace {
constexpr double kLn2 = 0.69314718055994531;
double normal_tail(double x) {
  return 0.5 * std::erfc(x / std::sqrt(2.0));
}  // P(Z > x)

// The halving below decides each step by whether normal_tail(mid) > q, that is whether mid lies below
// the answer. Far from the answer a close estimate decides that as surely and without erfc: a Newton
// estimate good to ~1e-14, trusted only beyond kSettled of it, where the tail differs from q by a
// relative x * 1e-12 or more, a thousand times what erfc and the argument's rounding can err by.
constexpr double kSettled = 1e-12;

// x with P(Z > x) = q for q < 1/2, by Newton's method from Abramowitz & Stegun 26.2.23 (error < 4.5e-4);
// NaN when it does not settle, or q is so small that erfc near the answer loses precision to underflow
// (the halving then evaluates every step).
double newton_tail_quantile(double q) {
  if (!(q > 1e-290 && q < 0.5)) return std::nan("");
  const double t = std::sqrt(-2 * std::log(q));
  double x =
      t - (2.515517 + t * (0.802853 + t * 0.010328)) / (1 + t * (1.432788 + t * (0.189269 + t * 0.001308)));
  constexpr double kInvSqrt2Pi = 0.39894228040143268;
  for (int k = 0; k < 8; ++k) {
    const double step = (normal_tail(x) - q) / (kInvSqrt2Pi * std::exp(-0.5 * x * x));
    x += step;
    if (std::abs(step) < 1e-14) return x > 0 ? x : std::nan("");
  }
  return std::nan("");
}

// The first kSkipped halvings toward a known answer, at once. A step whose midpoint lies farther than
// kSettled from the guess goes the guess's way, and the midpoints of the first kSkipped steps all lie on
// the grid -40 + j w, w = 80 / 2^kSkipped. So if the guess is farther than kSettled from every point of
// that grid, those steps all went its way and left the ends at the grid points either side of it (exact
// doubles, as every midpoint so far was). Otherwise (about 3 % of draws) nothing is skipped.
constexpr int kSkipped = 40;
void skip_far_halvings(double guess, double& lo, double& hi, int& steps) {
  const double w = std::ldexp(80.0, -kSkipped), s = (guess + 40) / w;
  const double from_grid = std::min(s - std::floor(s), std::ceil(s) - s) * w;
  if (!(from_grid > kSettled + 1e-13)) return;  // (1e-13: more than s's rounding, ~1e-14 in x)
  lo = -40 + w * (std::ceil(s) - 1), hi = lo + w, steps = kSkipped;
}
}  // namespace

// x with P(Z > x) = q, by bisection on erfc (accurate in the far tail, where ejecta energies come from).
// The halving stops once a step leaves both ends where they were (about 60 steps in, when they are
// neighbouring doubles or one): every later step would do the same, so the answer is the 100 steps'.
// The Newton estimate only saves work: every step goes the way erfc would send it, so the answer is the
// plain halving's to the bit (gtest LammelSplash.TailQuantileIsThePlainHalvingsToTheBit).
double normal_tail_quantile(double q) {
  const double guess = newton_tail_quantile(q);
  const bool known = !std::isnan(guess);
  double lo = -40, hi = 40;
  int k = 0;
  if (known) skip_far_halvings(guess, lo, hi, k);
  for (; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    const bool below = known && std::abs(mid - guess) > kSettled ? mid < guess : normal_tail(mid) > q;
    double& end = below ? lo : hi;
    if (end == mid) break;
    end = mid;
  }
  return 0.5 * (lo + hi);
}

LammelParameters LammelParameters::paper2021() {
  return {};
}

LammelParameters LammelParameters::paper2021_effective() {
  return {"paper2021-effective", 0.9, 0.0, true, 0.06};
}

LammelParameters LammelParameters::lammel2017() {
  return {"lammel2017", 0.73, -0.18, true, 0.05};
}

namespace {
// The sets by name: the one list names() and named() read.
struct NamedSet {
  const char* name;
  LammelParameters (*make)();
};
constexpr NamedSet kNamedSets[] = {{"paper2021", &LammelParameters::paper2021},
                                   {"paper2021-effective", &LammelParameters::paper2021_effective},
                                   {"lammel2017", &LammelParameters::lammel2017}};
}  // namespace

const std::vector<std::string>& LammelParameters::names() {
  static const std::vector<std::string> known = [] {
    std::vector<std::string> n;
    for (const NamedSet& s : kNamedSets) n.emplace_back(s.name);
    return n;
  }();
  return known;
}

bool LammelParameters::is_named(const std::string& name) {
  return std::find(names().begin(), names().end(), name) != names().end();
}

std::string LammelParameters::names_quoted() {
  std::string quoted;
  for (const std::string& n : names()) quoted += (quoted.empty() ? "\"" : ", \"") + n + "\"";
  return quoted;
}

LammelParameters LammelParameters::named(const std::string& name) {
  for (const NamedSet& s : kNamedSets)
    if (name == s.name) return s.make();
  throw std::invalid_argument("unknown splash parameter set \"" + name + "\" (known: " + names_quoted() +
                              ")");
}

LammelCoefficients lammel_coefficients(const LammelParameters& p, double d1, double d2) {
  const double v1 = d1 * d1 * d1, v2 = d2 * d2 * d2, eps = p.restitution;
  const double eta = p.effective_eta ? eps * v1 / (v1 + eps * v2) : v1 / v2;
  const double alpha = (1 + eps) / (1 + eta) - 1;
  const double beta = 1 - (2.0 / 7.0) * (1 - p.tangential) / (1 + eta);
  const double ratio = beta / (alpha + beta);
  return {eta, alpha, beta, 2 * (d1 + d2) / (9 * d2) * ratio * ratio};
}

double mean_restitution(const LammelCoefficients& c, double d1, double d2, double theta) {
  return c.beta - (c.beta * c.beta - c.alpha * c.alpha) * d2 * theta / (c.beta * (d1 + d2));
}

double rebound_angle(const LammelCoefficients& c, double theta, double u) {
  // F(s) = s (1 - ln s) rises from 0 to 1 on (0, 1] with F' = -ln s: Newton from the right, where F is
  // concave, converges monotonically.
  u = std::clamp(u, 1e-300, 1.0);
  double s = 1;
  for (int k = 0; k < 60 && s > 0; ++k) {
    const double f = s * (1 - std::log(s)) - u, slope = -std::log(s);
    if (slope <= 0) {
      s = 0.5 * (1 + u);  // s = 1 is the flat top: step into the interior first
      continue;
    }
    const double next = std::max(s - f / slope, 0.5 * s);
    if (std::abs(next - s) < 1e-15 * s) break;
    s = next;
  }
  return std::sqrt(s * 2 * theta / c.gamma) - theta;
}

double mean_rebound_angle(const LammelCoefficients& c, double theta) {
  return 4 * std::sqrt(2.0) / 9 * std::sqrt(theta / c.gamma) - theta;
}

EjectaLaw ejecta_law(const LammelParameters& p, double e_bar, double e1, double e_d2) {
  EjectaLaw law;
  law.e_d2 = e_d2;
  const double available = (1 - e_bar * e_bar) * e1, x = available / e_d2;
  if (!(x > 1)) return law;  // the rebound keeps too much: no bed grain can be lifted
  const double lambda = 2 * std::log(x);
  law.sigma = std::sqrt(lambda) * kLn2;
  law.mu_e = std::log(available) - lambda * kLn2;
  law.escape_probability = normal_tail((std::log(e_d2) - law.mu_e) / law.sigma);
  law.mean_count = p.ejecta_fraction * std::pow(x, (2 - kLn2) * kLn2) * law.escape_probability;
  return law;
}

double EjectaLaw::mean_energy() const {
  if (escape_probability <= 0) return 0;
  const double a = (std::log(e_d2) - mu_e) / sigma;
  return std::exp(mu_e + 0.5 * sigma * sigma) * normal_tail(a - sigma) / normal_tail(a);
}

int sample_ejecta_count(const EjectaLaw& law, Rng& rng) {
  const double whole = std::floor(law.mean_count);
  return static_cast<int>(whole) + (rng.uniform() < law.mean_count - whole ? 1 : 0);
}

double sample_ejectum_energy(const EjectaLaw& law, Rng& rng) {
  // The lognormal above e_d2, by inverting its CDF over the tail.
  const double q = law.escape_probability * (1 - rng.uniform());  // in (0, P(E2 > e_d2)]
  return std::exp(law.mu_e + law.sigma * normal_tail_quantile(q));
}

}  // namespace grainlab::ripples::hybrid
