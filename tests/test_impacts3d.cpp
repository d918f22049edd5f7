// Ch. III's impacts with spheres: a small poured bed, struck as in CASE A. The rebound and the ejecta
// cannot carry away more energy than the incident grain brought, and the ensemble (gathered as rows over
// MPI ranks) returns the same impacts as running them one by one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "impacts3d.hpp"
#include "input_error.hpp"
#include "sand_gun3d.hpp"
#include "sand_spheres3d.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::validation {

namespace {

// Built once for the tests below (about 5 s).
const Bed3d& small_bed() {
  static const Bed3d bed = [] {
    Bed3dSpec spec;
    spec.count = 360;
    spec.width = 16, spec.depth = 12;
    return build_bed3d(spec);
  }();
  return bed;
}

struct TempFile {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("grainlab-ck-" + std::to_string(::getpid()) + ".h5");
  ~TempFile() { std::filesystem::remove(path); }
};

// Writes 120 seeded corruptions (1-3 flipped bytes each) of `bytes` to `path` and hands each to `read`,
// which must either read it (and check what it got) or throw InputError; returns how many were refused.
template <class Read>
int refused_corruptions(const std::string& bytes, const std::filesystem::path& path, std::uint64_t seed,
                        Read read) {
  std::mt19937_64 rng(seed);
  int refused = 0;
  for (int k = 0; k < 120; ++k) {
    std::string m = bytes;
    for (int e = 0; e < 1 + static_cast<int>(rng() % 3); ++e)
      m[rng() % m.size()] ^= static_cast<char>(1 + rng() % 255);
    std::ofstream(path, std::ios::binary) << m;
    try {
      read();
    } catch (const InputError&) {
      ++refused;
    }
  }
  return refused;
}

void expect_same_impact(const Impact3dResult& a, const Impact3dResult& b) {
  EXPECT_EQ(a.rebounded, b.rebounded);
  EXPECT_EQ(a.vx, b.vx);
  EXPECT_EQ(a.vz, b.vz);
  EXPECT_EQ(a.x_impact, b.x_impact);
  ASSERT_EQ(a.ejecta.size(), b.ejecta.size());
  for (std::size_t k = 0; k < a.ejecta.size(); ++k) {
    EXPECT_EQ(a.ejecta[k].id, b.ejecta[k].id);
    EXPECT_EQ(a.ejecta[k].vz_launch, b.ejecta[k].vz_launch);
    EXPECT_EQ(a.ejecta[k].time, b.ejecta[k].time);
  }
}

TEST(Impacts3d, SpheresStruckAsCaseAGiveBackNoMoreEnergyThanTheyGet) {
  const Bed3d& bed = small_bed();
  // 360 spheres of 4.19 cm^3 in 16 x 12 cm at packing ~0.55: about 14 cm deep.
  EXPECT_GT(bed.top, 10.0);
  EXPECT_LT(bed.top, 20.0);
  const ImpactCase& c = impact_case("A");
  ImpactOptions o;
  o.duration = 0.03;
  const std::vector<Impact3dResult> all = run_impact3d_ensemble(bed, c, 3, 2, o);
  ASSERT_EQ(all.size(), 2u);
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Impact3dResult& r = all[k];
    const Impact3dResult one = run_impact3d(bed, c, 3, k, o);
    EXPECT_EQ(one.ejecta.size(), r.ejecta.size());
    EXPECT_EQ(one.rebounded, r.rebounded);
    EXPECT_EQ(one.vx, r.vx);
    EXPECT_NEAR(r.incident_mass, 2 * M_PI, 1e-12);  // the thesis disc's mass
    const Impact3dSummary s = summarize_impacts3d({r});
    // Kinetic energy out (rebound and ejecta where they left the bed) over in. The incident grain falls
    // about 1 cm after release, which releases 2e-4 of its energy.
    const double out = (r.rebounded ? std::pow(s.q.at("eps_i").mean, 2) : 0) + s.q.at("ej_energy").mean;
    EXPECT_LT(out, 1.0 + 2e-4) << "impact " << k;
    EXPECT_GT(out, 0.0);
    if (r.rebounded) {
      EXPECT_GT(r.vz, 0);
    }
  }
}

// An impact's active zone: a zone wider than the bed changes nothing, bit for bit; a zone of a few
// grains still gives an impact that returns no more energy than it got, and only grains inside the zone
// can be ejected (the rest are held in place).
TEST(Impacts3d, OnlyGrainsInsideTheActiveZoneMove) {
  const Bed3d& bed = small_bed();
  const ImpactCase& c = impact_case("A");
  ImpactOptions o;
  o.duration = 0.03;
  const Impact3dResult whole = run_impact3d(bed, c, 3, 0, o);
  ImpactOptions wide = o;
  wide.active_radius = 1e6;
  expect_same_impact(run_impact3d(bed, c, 3, 0, wide), whole);
  ImpactOptions zone = o;
  zone.active_radius = 8 * bed.spec.radius;  // four grain diameters
  for (std::size_t run = 0; run < 2; ++run) {
    const Impact3dResult r = run_impact3d(bed, c, 3, run, zone);
    const Impact3dSummary s = summarize_impacts3d({r});
    const double out = (r.rebounded ? std::pow(s.q.at("eps_i").mean, 2) : 0) + s.q.at("ej_energy").mean;
    EXPECT_LT(out, 1.0 + 2e-4) << "impact " << run;
    for (const Ejectum3d& e : r.ejecta)
      EXPECT_LE(std::sqrt(e.x0 * e.x0 + e.y0 * e.y0 + e.z0 * e.z0), zone.active_radius)
          << "a grain held in place was ejected (impact " << run << ", grain " << e.id << ")";
  }
  ImpactOptions on_ode = zone;
  on_ode.engine = "ode";
  EXPECT_THROW(run_impact3d(bed, c, 3, 0, on_ode), InputError);
}

// A checkpoint's impacts belong to one active zone: a file holding impacts of the whole bed is refused
// for a zone (and the other way round), naming --active-zone; a file holding only the built bed serves
// any zone, so one bed can be shot with several.
TEST(SandGunCheckpoint, KeepsImpactsOfOneActiveZoneOnly) {
  const Bed3d& bed = small_bed();
  SandGunProgress p;
  p.bed = bed;
  p.build = build_record(bed);
  p.build.finished = true;
  TempFile f;
  write_sand_gun_checkpoint(f.path.string(), p, 3);
  ASSERT_TRUE(read_sand_gun_checkpoint(f.path.string(), bed.spec, 3, sand_gun_impacts_of(8)));
  ImpactOptions o;
  o.duration = 0.03;
  p.done[{1, 0}] = run_impact3d(bed, impact_case("A"), 3, 0, o);
  write_sand_gun_checkpoint(f.path.string(), p, 3);
  for (const double zone : {8.0, 12.0}) {
    try {
      read_sand_gun_checkpoint(f.path.string(), bed.spec, 3, sand_gun_impacts_of(zone));
      ADD_FAILURE() << "impacts of the whole bed were lent to a zone of " << zone;
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("--active-zone"), std::string::npos) << e.message();
    }
  }
  write_sand_gun_checkpoint(f.path.string(), p, 3, sand_gun_impacts_of(8));
  EXPECT_TRUE(read_sand_gun_checkpoint(f.path.string(), bed.spec, 3, sand_gun_impacts_of(8)));
  EXPECT_THROW(read_sand_gun_checkpoint(f.path.string(), bed.spec, 3), InputError);
  EXPECT_THROW(read_sand_gun_checkpoint(f.path.string(), bed.spec, 3, sand_gun_impacts_of(4)), InputError);
}

// A sand-gun checkpoint keeps the bed bit for bit and the impacts as they were: the bed read back gives the
// same impact as the bed that was built, so a continued run computes what an unbroken one would.
// CASE G's preparation: poured, stiffened and damped without friction, the spheres slide toward random
// close packing (0.64 for equal spheres: Scott & Kilgour 1969, 0.6366; +- 0.03 for what the interior of
// this small bed, a few dozen spheres' volume, samples), well above what the same pour with friction 0.5
// locks into (0.55 here: random loose packing is no lower than 0.536, Song, Wang & Makse 2008). With its
// friction back the bed must hold still as the loose one does (the 2-D limits: 0.05 cm, 1 cm/s over an
// impact's 0.07 s), and a case for the other preparation is refused.
TEST(Impacts3d, DensePreparationPacksTowardRandomClosePacking) {
  Bed3dSpec spec = small_bed().spec;
  spec.preparation = "dense";
  const Bed3d dense = build_bed3d(spec);
  RecordProperty("dense_packing", std::to_string(dense.packing_fraction));
  RecordProperty("loose_packing", std::to_string(small_bed().packing_fraction));
  EXPECT_GT(dense.packing_fraction, small_bed().packing_fraction + 0.02);
  EXPECT_GT(dense.packing_fraction, 0.64 - 0.03);
  EXPECT_LT(dense.packing_fraction, 0.64 + 0.03);
  const BedHold h = hold_bed3d(dense, "native", 0.07, 1e-5);
  EXPECT_LT(h.max_displacement, 0.05);
  EXPECT_LT(h.max_speed, 1.0);
  EXPECT_THROW(run_impact3d(dense, impact_case("A"), 1, 0, ImpactOptions{}), std::invalid_argument);
  spec.preparation = "packed";
  EXPECT_THROW(build_bed3d(spec), InputError);
}

// A bed of polyhedra is measured by their shapes, not by their bounding spheres: cubes of side 2 on a
// pitch of 3 fill 8 / 27 = 0.296 of the space (their bounding spheres, radius sqrt 3, would fill about
// 0.7; spheres of radius 1, 0.155), and cubes turned 45 deg about x reach sqrt 2 above their centres.
TEST(Impacts3d, PolyhedralBedsAreMeasuredByTheirShapes) {
  Bed3dSpec spec;
  spec.polyhedra = true;
  spec.width = spec.depth = 30;
  std::vector<Body3Spec> cubes;
  const Quat turned(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()));
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        Body3Spec& b = cubes.emplace_back();
        b.id = static_cast<std::int64_t>(cubes.size()) - 1;
        b.shape = Body3Spec::Shape::Polyhedron;
        b.hull = make_box(Vec3(1, 1, 1));
        b.radius = b.hull.bounding_radius();
        b.mass = 8, b.inertia = Mat3::Identity() * (8.0 / 6);
        b.position = Vec3(1.5 + 3 * i, 1.5 + 3 * j, 1.5 + 3 * k);
      }
  const Bed3d upright = bed3d_from_bodies(spec, cubes);
  EXPECT_DOUBLE_EQ(upright.top, 16.5 + 1);
  EXPECT_NEAR(upright.packing_fraction, 8.0 / 27, 0.05);
  for (Body3Spec& b : cubes) b.orientation = turned;
  EXPECT_NEAR(bed3d_from_bodies(spec, cubes).top, 16.5 + std::sqrt(2.0), 1e-12);
}

TEST(SandGunCheckpoint, KeepsTheBedAndTheImpactsExactly) {
  const Bed3d& bed = small_bed();
  const ImpactCase& c = impact_case("A");
  ImpactOptions o;
  o.duration = 0.03;
  SandGunProgress p;
  p.bed = bed;
  p.done[{1, 0}] = run_impact3d(bed, c, 3, 0, o);
  p.done[{4, 7}] = run_impact3d(bed, c, 3, 1, o);
  ASSERT_GT(p.done.at({1, 0}).ejecta.size() + p.done.at({4, 7}).ejecta.size(), 0u);
  TempFile f;
  write_sand_gun_checkpoint(f.path.string(), p, 3);
  const std::optional<SandGunProgress> back = read_sand_gun_checkpoint(f.path.string(), bed.spec, 3);
  ASSERT_TRUE(back);
  const auto& a = bed.scene.bodies3d;
  const auto& b = back->bed.scene.bodies3d;
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].position, b[i].position);
    EXPECT_EQ(a[i].orientation.coeffs(), b[i].orientation.coeffs());
    EXPECT_EQ(a[i].radius, b[i].radius);
    EXPECT_EQ(a[i].mass, b[i].mass);
    EXPECT_EQ(a[i].inertia, b[i].inertia);
  }
  EXPECT_EQ(back->bed.top, bed.top);
  EXPECT_EQ(back->bed.probes, bed.probes);
  EXPECT_EQ(back->bed.build_stages, bed.build_stages);  // the finished bed's own record, not a reset one
  EXPECT_GT(bed.build_stages, 13);
  EXPECT_TRUE(back->build.finished);
  ASSERT_EQ(back->done.size(), 2u);
  expect_same_impact(back->done.at({1, 0}), p.done.at({1, 0}));
  expect_same_impact(back->done.at({4, 7}), p.done.at({4, 7}));
  expect_same_impact(run_impact3d(back->bed, c, 3, 1, o), p.done.at({4, 7}));
  // Another seed or bed is refused, naming the option; no file is no checkpoint.
  EXPECT_THROW(read_sand_gun_checkpoint(f.path.string(), bed.spec, 4), InputError);
  Bed3dSpec other = bed.spec;
  other.k_n *= 2;
  EXPECT_THROW(read_sand_gun_checkpoint(f.path.string(), other, 3), InputError);
  EXPECT_FALSE(read_sand_gun_checkpoint(f.path.string() + ".none", bed.spec, 3));
}

// The suite's cases keep their impacts in a file of their own (validate --sand-gun-checkpoint): two of
// four kept, the run continued from the file gives the ensemble's four bit for bit; the file is refused
// for a bed with one sphere elsewhere (a build by another binary, an engine's own settled bed).
TEST(SandGunCheckpoint, ASuiteCaseContinuedFromItsFileGivesTheSameImpacts) {
  const Bed3d& bed = small_bed();
  const ImpactCase& c = impact_case("A");
  ImpactOptions o;
  o.duration = 0.03;
  const std::vector<Impact3dResult> whole = run_impact3d_ensemble(bed, c, 1, 4, o);
  TempFile f;
  const std::vector<Impact3dResult> first = kept_case_impacts(f.path.string(), bed, c, 2, 1, o, {});
  ASSERT_EQ(first.size(), 2u);
  ASSERT_TRUE(std::filesystem::exists(f.path));
  const std::vector<Impact3dResult> all = kept_case_impacts(f.path.string(), bed, c, 4, 1, o, {});
  ASSERT_EQ(all.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) expect_same_impact(all[i], whole[i]);
  Bed3d moved = bed;
  moved.scene.bodies3d[17].position.x() += 1e-12;
  try {
    kept_case_impacts(f.path.string(), moved, c, 4, 1, o, {});
    ADD_FAILURE() << "a file kept for another bed lent its impacts";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--sand-gun-checkpoint");
  }
  ImpactOptions other = o;
  other.engine = "ode";
  EXPECT_THROW(kept_case_impacts(f.path.string(), bed, c, 4, 1, other, {}), InputError);
}

// An impulse engine squeezes a bed built on the soft-contact engine further (ODE moved this one 0.054 cm
// in 0.07 s as built, past the 0.05 cm limit). Settled on the engine itself, the bed it hands back rests
// there; a bed already at rest on an engine (native) comes back untouched.
TEST(Impacts3d, ABedSettledOnAnImpulseEngineRestsThere) {
  const Bed3d& bed = small_bed();
  const AtRestLimits limits = at_rest_limits(bed.spec);
  const EngineBed same = settle_on_engine(bed, "native", 0.2, 4, 0.07, ImpactOptions{}.rigid_dt);
  EXPECT_EQ(same.settles, 0);
  ASSERT_EQ(same.bed.scene.bodies3d.size(), bed.scene.bodies3d.size());
  for (std::size_t i = 0; i < bed.scene.bodies3d.size(); ++i)
    EXPECT_EQ(same.bed.scene.bodies3d[i].position, bed.scene.bodies3d[i].position);
  const EngineBed ode = settle_on_engine(bed, "ode", 0.2, 4, 0.07, ImpactOptions{}.rigid_dt);
  EXPECT_LE(ode.settles, 4);
  EXPECT_LT(ode.hold.max_displacement, limits.displacement);
  EXPECT_LT(ode.hold.max_speed, limits.speed);
  if (ode.settles > 0) {  // then the spheres are where ODE left them, lower on the whole
    double sank = 0;
    for (std::size_t i = 0; i < bed.scene.bodies3d.size(); ++i)
      sank += bed.scene.bodies3d[i].position.z() - ode.bed.scene.bodies3d[i].position.z();
    EXPECT_GT(sank, 0);
  }
}

// When the probes run out, the build holds the bed (left alone for an impact's duration from rest, taken
// where it stopped) until no sphere breaks the bed-at-rest limits, at most four times. On a small sand bed:
// - after one probe (it takes the loose grains away and leaves 4 deep spheres settling) the holds bring
//   the bed to rest, and it passes the suite's own bed-at-rest test;
// - with no probe, a loose grain keeps rolling in its pocket (this contact law has no rolling
//   resistance), so the bed is held again and again; a bed handed over before the fourth hold is at rest.
// Either way the build's record counts what the suite's test finds.
TEST(Impacts3d, ABedStillSettlingIsHeldUntilAtRest) {
  int most_holds = 0;
  for (int probes : {1, 0}) {
    Bed3dSpec spec = sand_gun_bed_spec(400);
    spec.max_probes = probes;
    const Bed3d bed = build_bed3d(spec);
    const int holds = build_holds(bed);
    const BedHold h = hold_bed3d(bed, "native", sand_gun_options(spec).duration, 1e-5);
    const AtRestLimits limits = at_rest_limits(spec);
    const std::size_t over = grains_over(h, limits);
    EXPECT_EQ(over, bed.deep_movers) << probes << " probes";
    EXPECT_GE(holds, 1) << probes << " probes";
    EXPECT_LE(holds, 4) << probes << " probes";
    if (holds < 4) {
      EXPECT_EQ(over, 0u) << probes << " probes";
    }
    if (probes == 1) {
      EXPECT_EQ(bed.probes, 1u);
      EXPECT_LT(h.max_displacement, limits.displacement);
      EXPECT_LT(h.max_speed, limits.speed);
    }
    most_holds = std::max(most_holds, holds);
  }
  EXPECT_GT(most_holds, 1);  // a bed was held again from where a hold left it
}

// The hold's report names how many grains break a limit and how deep the largest mover sits, so a reader
// can tell a rattler deep in the bed from the surface moving. Three grains: one deep and fast, one at the
// top slow but displaced, one at rest.
TEST(Impacts3d, TheHoldSaysWhereTheBedMoved) {
  BedHold h;
  h.displacement = {0.25, 0.09, 0.01};
  h.speed = {8.4, 0.2, 0.1};
  h.depth = {8.7, 0.9, 3.0};
  const AtRestLimits limits{0.05, 1.0};
  EXPECT_EQ(where_the_bed_moved(h, limits),
            "2 spheres over a limit; the one that moved most (0.25 cm) sits 8.7 cm below the top");
  EXPECT_EQ(where_the_bed_moved(BedHold{}, limits), "no spheres");
}

// A bed's build stopped after any stage, kept in a checkpoint and continued from it, makes the bed an
// unbroken build makes, bit for bit (a 20,000-sphere sand bed takes over an hour to build).
TEST(SandGunCheckpoint, ABuildContinuedFromAnyStageMakesTheSameBed) {
  Bed3dSpec spec;
  spec.count = 80;
  spec.width = 8, spec.depth = 6;
  std::vector<Bed3dBuild> stages;
  const Bed3d whole = build_bed3d(spec, {}, {}, [&](const Bed3dBuild& b) { stages.push_back(b); });
  ASSERT_GT(stages.size(), 13u);  // the pour, ten stiffening steps, damping, relaxing, one probe or more
  EXPECT_TRUE(stages.back().finished);
  EXPECT_EQ(whole.probes, stages.back().probes);
  EXPECT_EQ(whole.build_stages, stages.back().stage);
  for (std::size_t k : {std::size_t{0}, std::size_t{12}, stages.size() - 2}) {
    SandGunProgress p;
    p.build = stages[k];
    p.bed.spec = spec;
    TempFile f;
    write_sand_gun_checkpoint(f.path.string(), p, 1);
    const std::optional<SandGunProgress> back = read_sand_gun_checkpoint(f.path.string(), spec, 1);
    ASSERT_TRUE(back);
    ASSERT_FALSE(back->build.finished);
    EXPECT_EQ(back->build.stage, stages[k].stage);
    const Bed3d resumed = build_bed3d(spec, {}, back->build);
    const auto& a = whole.scene.bodies3d;
    const auto& b = resumed.scene.bodies3d;
    ASSERT_EQ(a.size(), b.size()) << "continued after stage " << k + 1;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position, b[i].position) << "sphere " << i;
    EXPECT_EQ(resumed.removed, whole.removed);
    EXPECT_EQ(resumed.top, whole.top);
  }
}

// The same from part-way through a stage (a probe of a 20,000-sphere sand bed runs for hours): handed over
// after every 2,000 steps here, with the stage's finished runs and the world of the run under way, kept in
// a checkpoint and continued from it, the build makes the unbroken build's bed bit for bit.
TEST(SandGunCheckpoint, ABuildContinuedFromPartWayThroughAStageMakesTheSameBed) {
  Bed3dSpec spec;  // (a bed whose probe finds spheres to deal with, so it runs three times)
  spec.count = 60;
  spec.width = 6, spec.depth = 6;
  std::vector<Bed3dBuild> within;  // records handed over inside a stage
  std::size_t between = 0;
  const Bed3d whole = build_bed3d(
      spec, {}, {},
      [&](const Bed3dBuild& b) {
        if (b.runs_done.rows.empty() && b.run_under_way.empty())
          ++between;
        else
          within.push_back(b);
      },
      0);
  ASSERT_GT(between, 13u);
  ASSERT_GT(within.size(), 3u);
  // Records inside the probe: its first run finished and the next under way; two finished.
  const auto in_probe = std::find_if(within.begin(), within.end(), [](const Bed3dBuild& b) {
    return !b.runs_done.rows.empty() && !b.run_under_way.empty();
  });
  ASSERT_NE(in_probe, within.end());
  const auto two_done = std::find_if(within.begin(), within.end(), [&](const Bed3dBuild& b) {
    return b.runs_done.rows.size() > in_probe->runs_done.rows.size();
  });
  ASSERT_NE(two_done, within.end());
  Bed3dBuild runs_only = *two_done;  // as if stopped between the probe's second and third runs
  runs_only.run_under_way.clear();
  for (const Bed3dBuild* r : {&within.front(), &*in_probe, &*two_done, &runs_only, &within.back()}) {
    SandGunProgress p;
    p.build = *r;
    p.bed.spec = spec;
    TempFile f;
    write_sand_gun_checkpoint(f.path.string(), p, 1);
    const std::optional<SandGunProgress> back = read_sand_gun_checkpoint(f.path.string(), spec, 1);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->build.stage, r->stage);
    EXPECT_EQ(back->build.runs_done.rows, r->runs_done.rows);
    EXPECT_EQ(back->build.run_under_way.size(), r->run_under_way.size());
    const Bed3d resumed = build_bed3d(spec, {}, back->build);
    const auto& a = whole.scene.bodies3d;
    const auto& b = resumed.scene.bodies3d;
    ASSERT_EQ(a.size(), b.size()) << "continued inside stage " << r->stage + 1;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position, b[i].position) << "sphere " << i;
    EXPECT_EQ(resumed.removed, whole.removed);
    EXPECT_EQ(resumed.probes, whole.probes);
    EXPECT_EQ(resumed.top, whole.top);
  }
  // The continued stage does start from what the record holds: a sphere nudged in the world under way, or
  // in a finished run, ends elsewhere.
  auto moved_by = [&](Bed3dBuild r) {
    const Bed3d b = build_bed3d(spec, {}, std::move(r));
    double most = 0;
    for (std::size_t i = 0; i < b.scene.bodies3d.size() && i < whole.scene.bodies3d.size(); ++i)
      most = std::max(most, (b.scene.bodies3d[i].position - whole.scene.bodies3d[i].position).norm());
    return b.scene.bodies3d.size() == whole.scene.bodies3d.size() ? most : 1.0;
  };
  Bed3dBuild nudged = *in_probe;
  nudged.run_under_way.at(kStageWorld + std::string("bodies")).rows[7][1] += 0.3;  // x, cm
  EXPECT_GT(moved_by(nudged), 0);
  nudged = runs_only;
  nudged.runs_done.rows.back()[1] += 0.3;  // x, cm, after the run the next one starts from
  EXPECT_GT(moved_by(nudged), 0);
  // A world that does not fit its stage (one sphere too few) is refused with InputError, naming the option.
  Bed3dBuild bad = *in_probe;
  bad.run_under_way.at(kStageWorld + std::string("bodies")).rows.pop_back();
  try {
    build_bed3d(spec, {}, bad);
    ADD_FAILURE() << "a world of the wrong size was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--checkpoint");
  }
}

// Seeded corruption anywhere in a checkpoint: each mutant is read or refused with InputError.
TEST(SandGunCheckpoint, RandomByteFlipsNeverCrash) {
  const Bed3d& bed = small_bed();
  SandGunProgress p;
  p.bed = bed;
  ImpactOptions o;
  o.duration = 0.01;
  p.done[{2, 0}] = run_impact3d(bed, impact_case("A"), 5, 0, o);
  TempFile good, mutant;
  write_sand_gun_checkpoint(good.path.string(), p, 5);
  std::ifstream in(good.path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const int refused = refused_corruptions(bytes, mutant.path, 2031, [&] {
    const std::optional<SandGunProgress> r = read_sand_gun_checkpoint(mutant.path.string(), bed.spec, 5);
    ASSERT_TRUE(r);
    EXPECT_EQ((r->build.finished ? r->bed.scene.bodies3d : r->build.bodies).size(),
              bed.scene.bodies3d.size());
  });
  EXPECT_GT(refused, 0);
}

// The same for a checkpoint written inside a stage (its finished runs and the world under way): each
// mutant is refused, or read and continued to a bed, with InputError at worst.
TEST(SandGunCheckpoint, RandomByteFlipsInAStageUnderWayNeverCrash) {
  Bed3dSpec spec;
  spec.count = 60;
  spec.width = 6, spec.depth = 6;
  Bed3dBuild last;  // the last record inside a stage: the final probe's run, so a continuation is short
  build_bed3d(
      spec, {}, {},
      [&](const Bed3dBuild& b) {
        if (!b.run_under_way.empty()) last = b;
      },
      0);
  ASSERT_FALSE(last.run_under_way.empty());
  SandGunProgress p;
  p.build = last;
  p.bed.spec = spec;
  TempFile good, mutant;
  write_sand_gun_checkpoint(good.path.string(), p, 1);
  std::ifstream in(good.path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const int refused = refused_corruptions(bytes, mutant.path, 2029, [&] {
    const std::optional<SandGunProgress> r = read_sand_gun_checkpoint(mutant.path.string(), spec, 1);
    ASSERT_TRUE(r);
    if (!r->build.finished) build_bed3d(spec, {}, r->build);
  });
  EXPECT_GT(refused, 0);
}

// A bed of irregular grains mid-build (its shapes from a random pour) comes back from a checkpoint with
// every hull exactly; corrupted hulls are refused with InputError, never a crash.
TEST(SandGunCheckpoint, KeepsIrregularGrainsHulls) {
  const Scene pour = parse_scene(std::string("[scene]\nname = \"irregular sand\"\ndimension = 3\nduration = "
                                             "0.01\nseed = 7\n") +
                                     kSandSpheres3dOnAFloor + R"toml([[assemblies]]
type = "poured"
count = 12
width = 4.0
depth = 4.0
origin = [0.0, 0.0, 0.0]
density = 2.65
settle_time = 0.1
shape = "polyhedron"
radius = 0.4
)toml",
                                 "<irregular sand>");
  SandGunProgress p;
  p.bed.spec.polyhedra = true;
  p.build.stage = 1;
  p.build.bodies = dem::expanded_bodies3d(pour);
  ASSERT_EQ(p.build.bodies.size(), 12u);
  TempFile f;
  write_sand_gun_checkpoint(f.path.string(), p, 2);
  const std::optional<SandGunProgress> back = read_sand_gun_checkpoint(f.path.string(), p.bed.spec, 2);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->build.bodies.size(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    const Polyhedron &a = p.build.bodies[i].hull, &b = back->build.bodies[i].hull;
    EXPECT_EQ(back->build.bodies[i].shape, Body3Spec::Shape::Polyhedron);
    EXPECT_EQ(a.vertices, b.vertices) << "grain " << i;
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.offsets, b.offsets);
    EXPECT_EQ(a.edge_faces, b.edge_faces);
  }
  // A sphere bed's reading of the same file is refused (another bed), and corruption is refused.
  EXPECT_THROW(read_sand_gun_checkpoint(f.path.string(), Bed3dSpec{}, 2), InputError);
  std::ifstream in(f.path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  in.close();
  const int refused = refused_corruptions(bytes, f.path, 2032, [&] {
    const std::optional<SandGunProgress> r = read_sand_gun_checkpoint(f.path.string(), p.bed.spec, 2);
    ASSERT_TRUE(r);
    for (const Body3Spec& b : r->build.bodies) EXPECT_FALSE(b.hull.faces.empty());
  });
  EXPECT_GT(refused, 0);
}

}  // namespace

}  // namespace grainlab::validation
