#include <fmt/format.h>

#include "dem_saltation_state.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"

namespace grainlab::validation::dem_saltation_detail {

namespace {

constexpr const char* kKind = "grainlab-dem-saltation-checkpoint/1";
const std::vector<std::string> kTrackColumns = {"x",    "y",    "vx",    "vy",    "x_unwrapped", "airborne",
                                                "up_t", "up_x", "up_vx", "up_vy", "up_grain",    "peak"};
const std::vector<std::string> kFlightColumns = {"t_up", "height", "length", "impact_vx", "impact_vy"};
const std::vector<std::string> kCrossingColumns = {"t", "x", "vx", "vy", "grain"};
const std::vector<std::string> kSeriesColumns = {"t", "mass_flux", "u_star_eff", "airborne"};
const std::vector<std::string> kWindowColumns = {"mass_flux", "u_star_eff",       "airborne",    "grain_gain",
                                                 "wind_loss", "stress_partition", "coupling_lag"};
const std::vector<std::string> kProfileColumns = {"mass", "flux", "wind", "wind_clean", "grain_stress"};
const std::vector<std::string> kClockColumns = {"next_sample"};

// Everything that decides what the run computes: the scene and the sampling. A checkpoint from other
// options would continue a different run. The rank count is not among them: the world is bitwise the same
// on any number of ranks, so a run stopped on two may continue on one.
std::string fingerprint(const DemSaltationOptions& o) {
  return fmt::format(
      "{}\n[sampling]\naverage_from = {:.17g}\nsample_interval = {:.17g}\nsplash_window = "
      "{:.17g}\nsplash_reach = {:.17g}\n",
      dem_saltation_scene(o), o.average_from, o.sample_interval, o.splash_window, o.splash_reach);
}

Crossing crossing_of(const std::vector<double>& r, std::size_t at) {
  return {r[at], r[at + 1], r[at + 2], r[at + 3], static_cast<std::size_t>(r[at + 4])};
}

SampleTable crossing_table(const std::string& name, const std::vector<Crossing>& list) {
  SampleTable t{name, "crossings of one diameter above the bed in the window", kCrossingColumns, {}};
  for (const Crossing& c : list) t.rows.push_back({c.t, c.x, c.vx, c.vy, static_cast<double>(c.grain)});
  return t;
}

template <std::size_t N>
std::vector<std::array<double, N>> fixed_rows(const SampleTable& t) {
  std::vector<std::array<double, N>> out;
  for (const auto& r : t.rows) {
    std::array<double, N> a{};
    std::copy(r.begin(), r.begin() + N, a.begin());
    out.push_back(a);
  }
  return out;
}

}  // namespace

void write_checkpoint(const std::string& path, const DemSaltationOptions& o, const dem::WorldState& world,
                      const StudyState& s) {
  std::vector<SampleTable> tables = dem::state_tables(world, "state/");
  SampleTable track{
      "study/tracks", "each grain at the last sample and its current flight", kTrackColumns, {}};
  for (const GrainTrack& g : s.track)
    track.rows.push_back({g.x, g.y, g.vx, g.vy, g.x_unwrapped, g.airborne ? 1.0 : 0.0, g.up.t, g.up.x,
                          g.up.vx, g.up.vy, static_cast<double>(g.up.grain), g.peak});
  SampleTable flights{"study/flights", "hops that started in the window", kFlightColumns, {}};
  for (const Flight& f : s.flights)
    flights.rows.push_back({f.t_up, f.height, f.length, f.impact_vx, f.impact_vy});
  SampleTable series{"study/series", "every 10th sample", kSeriesColumns, {}};
  for (const auto& r : s.series) series.rows.push_back({r.begin(), r.end()});
  SampleTable window{"study/window", "every sample of the steady-state window", kWindowColumns, {}};
  for (const auto& r : s.window) window.rows.push_back({r.begin(), r.end()});
  SampleTable profiles{"study/profiles", "sums over the window's samples per bin", kProfileColumns, {}};
  for (std::size_t k = 0; k < s.mass_z.size(); ++k)
    profiles.rows.push_back({s.mass_z[k], s.flux_z[k], s.wind_z[k], s.clean_z[k], s.tau_z[k]});
  SampleTable clock{"study/clock", "the next sample", kClockColumns, {{static_cast<double>(s.next_sample)}}};
  tables.insert(tables.end(),
                {track, flights, crossing_table("study/impacts", s.impacts),
                 crossing_table("study/liftoffs", s.liftoffs), series, window, profiles, clock});
  write_sample_tables(path, tables,
                      {{"kind", kKind}, {"grainlab_version", GRAINLAB_VERSION}, {"options", fingerprint(o)}});
}

std::pair<dem::WorldState, StudyState> read_checkpoint(const std::string& path,
                                                       const DemSaltationOptions& o) {
  auto wanted = dem::state_table_columns("state/");
  wanted.insert({{"study/tracks", kTrackColumns},
                 {"study/flights", kFlightColumns},
                 {"study/impacts", kCrossingColumns},
                 {"study/liftoffs", kCrossingColumns},
                 {"study/series", kSeriesColumns},
                 {"study/window", kWindowColumns},
                 {"study/profiles", kProfileColumns},
                 {"study/clock", kClockColumns}});
  const TableFile file = read_sample_tables(path, wanted);
  require_checkpoint(file, path, kKind, "saltation dem checkpoint", fingerprint(o),
                     "was written with other options (u*, bed, grains, duration or sampling): pass the "
                     "ones it was started with");
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--restart", why); };
  StudyState s;
  const auto& clock = file.tables.at("study/clock").rows;
  if (clock.size() != 1) refuse("has no clock row");
  s.next_sample = static_cast<long>(clock[0][0]);
  for (const auto& r : file.tables.at("study/tracks").rows)
    s.track.push_back({r[0], r[1], r[2], r[3], r[4], r[5] != 0, crossing_of(r, 6), r[11]});
  for (const auto& r : file.tables.at("study/flights").rows)
    s.flights.push_back({r[0], r[1], r[2], r[3], r[4]});
  for (const auto& r : file.tables.at("study/impacts").rows) s.impacts.push_back(crossing_of(r, 0));
  for (const auto& r : file.tables.at("study/liftoffs").rows) s.liftoffs.push_back(crossing_of(r, 0));
  s.series = fixed_rows<4>(file.tables.at("study/series"));
  s.window = fixed_rows<7>(file.tables.at("study/window"));
  for (const auto& r : file.tables.at("study/profiles").rows) {
    s.mass_z.push_back(r[0]), s.flux_z.push_back(r[1]), s.wind_z.push_back(r[2]);
    s.clean_z.push_back(r[3]), s.tau_z.push_back(r[4]);
  }
  try {
    return {dem::state_from_tables(file.tables, "state/"), std::move(s)};
  } catch (const std::exception& e) {
    refuse(e.what());
  }
  return {};
}

}  // namespace grainlab::validation::dem_saltation_detail
