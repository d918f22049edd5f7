#include "transient_checkpoint.hpp"

#include <cmath>

#include "h5_input.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"

namespace grainlab::saltation {

namespace {

constexpr const char* kKind = "grainlab-saltation-transient-checkpoint/1";
const std::vector<std::string> kScalarColumns = {"next_step", "next_change", "u_star", "since", "most",
                                                 "flux",      "airborne",    "over",   "died",  "failure"};
const std::vector<std::string> kBinColumns = {"born", "vox"};
const std::vector<std::string> kHeightColumns = {"drag"};
const std::vector<std::string> kLandingColumns = {"step", "flux", "airborne"};
const std::vector<std::string> kLandingBinColumns = {"step", "bin", "count", "vx", "vy"};
const std::vector<std::string> kLandingDragColumns = {"step", "height", "drag"};
const std::vector<std::string> kSampleColumns = {"t",        "u_star",    "launch_rate",
                                                 "airborne", "mass_flux", "u_star_eff"};
// The failures a run can end with, by number (0: none).
const std::vector<std::string> kFailures = {
    "", "the flux died out: u* is below the impact threshold for this splash",
    "the flux grows without bound: this splash replaces each grain more than once"};

SampleTable column_table(const std::string& name, const std::string& what,
                         const std::vector<std::string>& columns,
                         const std::vector<const std::vector<double>*>& values) {
  SampleTable t{name, what, columns, {}};
  for (std::size_t i = 0; i < values.front()->size(); ++i) {
    std::vector<double> row;
    for (const auto* v : values) row.push_back((*v)[i]);
    t.rows.push_back(row);
  }
  return t;
}

}  // namespace

void write_transient_checkpoint(const std::string& path, const TransientState& s,
                                const std::string& options) {
  double failure = 0;
  for (std::size_t k = 1; k < kFailures.size(); ++k)
    if (s.result.failure == kFailures[k]) failure = static_cast<double>(k);
  SampleTable scalars{
      "transient/scalars",
      "the run's clock and totals",
      kScalarColumns,
      {{static_cast<double>(s.next_step), static_cast<double>(s.next_change), s.u_star, s.since, s.most,
        s.flux, s.airborne, s.over ? 1.0 : 0.0, s.result.died ? 1.0 : 0.0, failure}}};
  SampleTable landings{
      "transient/landings", "per landing step: its flux and airborne count", kLandingColumns, {}};
  SampleTable bins{"transient/landing_bins",
                   "per landing step and launch bin: grains and summed impact velocity",
                   kLandingBinColumns,
                   {}};
  SampleTable drag{"transient/landing_drag",
                   "per landing step and height bin: the drag it takes away",
                   kLandingDragColumns,
                   {}};
  for (const auto& [step, L] : s.landings) {
    const double at = static_cast<double>(step);
    landings.rows.push_back({at, L.flux, L.airborne});
    for (std::size_t j = 0; j < L.count.size(); ++j)
      if (L.count[j] != 0 || L.vx[j] != 0 || L.vy[j] != 0)
        bins.rows.push_back({at, static_cast<double>(j), L.count[j], L.vx[j], L.vy[j]});
    for (std::size_t k = 0; k < L.drag.size(); ++k)
      if (L.drag[k] != 0) drag.rows.push_back({at, static_cast<double>(k), L.drag[k]});
  }
  SampleTable samples{"transient/samples", "the samples so far", kSampleColumns, {}};
  for (const TransientSample& x : s.result.samples)
    samples.rows.push_back({x.t, x.u_star, x.launch_rate, x.airborne, x.mass_flux, x.u_star_eff});
  write_sample_tables(
      path,
      {scalars, column_table("transient/bins", "per launch bin", kBinColumns, {&s.born, &s.vox}),
       column_table("transient/heights", "per height bin", kHeightColumns, {&s.drag}), landings, bins, drag,
       samples},
      {{"kind", kKind}, {"grainlab_version", GRAINLAB_VERSION}, {"options", options}});
}

TransientState read_transient_checkpoint(const std::string& path, const TransientOptions& o,
                                         const std::string& options) {
  const TableFile file = read_sample_tables(path, {{"transient/scalars", kScalarColumns},
                                                   {"transient/bins", kBinColumns},
                                                   {"transient/heights", kHeightColumns},
                                                   {"transient/landings", kLandingColumns},
                                                   {"transient/landing_bins", kLandingBinColumns},
                                                   {"transient/landing_drag", kLandingDragColumns},
                                                   {"transient/samples", kSampleColumns}});
  require_checkpoint(
      file, path, kKind, "saltation transient checkpoint", options,
      "was written with other options (splash, u*, changes, dt, duration or grain): pass the ones "
      "it was started with");
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--restart", why); };
  const std::size_t M = static_cast<std::size_t>(o.model.bins), H = height_nodes(o.model).size();
  const long last = transient_last_step(o);
  // A whole number in [lo, hi], or refused naming `what`.
  auto whole = [&](double v, double lo, double hi, const std::string& what) {
    if (!(v >= lo && v <= hi) || v != std::floor(v)) refuse(what + " out of range");
    return static_cast<long>(v);
  };
  const auto& sc = file.tables.at("transient/scalars").rows;
  if (sc.size() != 1) refuse("has no state row");
  TransientState s;
  const auto& r = sc[0];
  s.next_step = whole(r[0], 0, static_cast<double>(last) + 1, "the next step");
  s.next_change = static_cast<std::size_t>(
      whole(r[1], 0, static_cast<double>(o.ustar_changes.size()), "the next change"));
  s.u_star = r[2], s.since = r[3], s.most = r[4], s.flux = r[5], s.airborne = r[6];
  s.over = whole(r[7], 0, 1, "the run's end flag") == 1;
  s.result.died = whole(r[8], 0, 1, "the died flag") == 1;
  s.result.failure = kFailures[static_cast<std::size_t>(whole(r[9], 0, 2, "the failure"))];
  for (double v : {s.u_star, s.since, s.most, s.flux, s.airborne})
    if (!std::isfinite(v)) refuse("holds a value that is not finite");
  const auto& bins = file.tables.at("transient/bins").rows;
  const auto& heights = file.tables.at("transient/heights").rows;
  if (bins.size() != M || heights.size() != H) refuse("does not fit these options' launch and height grids");
  for (const auto& b : bins) s.born.push_back(b[0]), s.vox.push_back(b[1]);
  for (const auto& h : heights) s.drag.push_back(h[0]);
  // Landings lie after the step run last and within the longest flight; each bin and height once.
  auto landing = [&](double step) -> TransientLanding& {
    const long at = whole(step, static_cast<double>(s.next_step), 1e15, "a landing step");
    auto [it, fresh] = s.landings.try_emplace(at);
    if (fresh)
      it->second.count.assign(M, 0.0), it->second.vx.assign(M, 0.0), it->second.vy.assign(M, 0.0),
          it->second.drag.assign(H, 0.0);
    return it->second;
  };
  for (const auto& l : file.tables.at("transient/landings").rows) {
    const long at = whole(l[0], static_cast<double>(s.next_step), 1e15, "a landing step");
    if (s.landings.count(at)) refuse("lists a landing step twice");
    TransientLanding& L = landing(l[0]);
    L.flux = l[1], L.airborne = l[2];
  }
  for (const auto& b : file.tables.at("transient/landing_bins").rows) {
    if (!s.landings.count(whole(b[0], static_cast<double>(s.next_step), 1e15, "a landing step")))
      refuse("has landing grains at a step it does not list");
    TransientLanding& L = landing(b[0]);
    const auto j = static_cast<std::size_t>(whole(b[1], 0, static_cast<double>(M) - 1, "a launch bin"));
    L.count[j] = b[2], L.vx[j] = b[3], L.vy[j] = b[4];
  }
  for (const auto& d : file.tables.at("transient/landing_drag").rows) {
    if (!s.landings.count(whole(d[0], static_cast<double>(s.next_step), 1e15, "a landing step")))
      refuse("has landing drag at a step it does not list");
    landing(d[0]).drag[static_cast<std::size_t>(whole(d[1], 0, static_cast<double>(H) - 1, "a height bin"))] =
        d[2];
  }
  for (const auto& x : file.tables.at("transient/samples").rows)
    s.result.samples.push_back({x[0], x[1], x[2], x[3], x[4], x[5]});
  return s;
}

}  // namespace grainlab::saltation
