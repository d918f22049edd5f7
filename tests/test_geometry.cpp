#include <gtest/gtest.h>

#include <cmath>

#include "narrow_phase.hpp"
#include "polygon.hpp"

using namespace grainlab;
using namespace grainlab::dem;

TEST(Polygon, RectangleMassProperties) {
  const std::vector<Vec2> rect = {{1, 1}, {5, 1}, {5, 3}, {1, 3}};  // 4 x 2, centroid (3, 2)
  const PolygonMass m = polygon_mass(rect);
  EXPECT_DOUBLE_EQ(m.area, 8);
  EXPECT_NEAR(m.centroid.x, 3, 1e-12);
  EXPECT_NEAR(m.centroid.y, 2, 1e-12);
  EXPECT_NEAR(m.polar_moment_per_density, 8 * (16 + 4) / 12.0, 1e-9);
  EXPECT_TRUE(is_convex_ccw(rect));
  EXPECT_FALSE(is_convex_ccw({{1, 1}, {1, 3}, {5, 3}, {5, 1}}));  // clockwise
}

namespace {
const std::vector<Vec2> kSquare = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
}

TEST(NarrowPhase, SquareOnSquareAlignedFaceDepthIsThePenetration) {
  std::vector<Vec2> sa, sb;
  ContactGeometry c;
  // A narrower face resting on a wider one: the outlines cross at the two ends of the contact.
  const std::vector<Vec2> narrow = {{-0.8, -1}, {0.8, -1}, {0.8, 1}, {-0.8, 1}};
  BodyPose top{{0, 1.95}, 0, 2.0, &narrow}, bottom{{0, 0}, 0, 2.0, &kSquare};
  ASSERT_TRUE(body_body_contact(top, bottom, c, sa, sb));
  EXPECT_NEAR(c.depth, 0.05, 1e-12);
  EXPECT_NEAR(c.normal.y, 1, 1e-12);
}

TEST(NarrowPhase, OffsetFacesTiltTheContactLineByDepthOverLength) {
  // The thesis's contact line joins the outline crossings; for faces offset sideways these are opposite
  // corners of the overlap, so the normal tilts by ~depth/length and the width along it counts both
  // penetrating corners (docs/physics.md). Both effects shrink with the overlap.
  std::vector<Vec2> sa, sb;
  ContactGeometry c;
  BodyPose top{{0.3, 1.95}, 0, std::sqrt(2.0), &kSquare}, bottom{{0, 0}, 0, std::sqrt(2.0), &kSquare};
  ASSERT_TRUE(body_body_contact(top, bottom, c, sa, sb));
  EXPECT_NEAR(std::atan2(c.normal.x, c.normal.y), std::atan2(0.05, 1.7), 1e-9);
  EXPECT_GT(c.depth, 0.05);
  EXPECT_LT(c.depth, 0.1);
}

TEST(NarrowPhase, DiscOnPolygonFaceMatchesDiscOnLine) {
  std::vector<Vec2> sa, sb;
  ContactGeometry poly, line;
  BodyPose disc{{0.2, 1.4}, 0, 0.5, nullptr}, square{{0, 0}, 0, std::sqrt(2.0), &kSquare};
  ASSERT_TRUE(body_body_contact(disc, square, poly, sa, sb));
  Wall floor;
  floor.spec.kind = WallSpec::Kind::Line;
  floor.spec.a = {0, 1};
  floor.spec.b = {0, 1};
  floor.at(0);
  ASSERT_TRUE(disc_wall_contact(disc.centre, 0.5, floor, line));
  EXPECT_NEAR(poly.depth, line.depth, 1e-12);
  EXPECT_NEAR(poly.normal.y, 1, 1e-12);
}

TEST(NarrowPhase, VertexIntoFaceDepthIsVertexPenetration) {
  std::vector<Vec2> sa, sb;
  ContactGeometry c;
  // A square standing on its corner, the corner 0.1 below the other square's top face.
  BodyPose corner{{0, 1 + std::sqrt(2.0) - 0.1}, M_PI / 4, std::sqrt(2.0), &kSquare},
      base{{0, 0}, 0, std::sqrt(2.0), &kSquare};
  ASSERT_TRUE(body_body_contact(corner, base, c, sa, sb));
  EXPECT_NEAR(c.depth, 0.1, 1e-9);
  EXPECT_NEAR(c.normal.y, 1, 1e-9);
}

TEST(NarrowPhase, SegmentEndPointRulePushesRadially) {
  Wall seg;
  seg.spec.a = {-5, 0};
  seg.spec.b = {0, 0};
  seg.at(0);
  ContactGeometry c;
  // Centre past the end: the end point penetrates the disc, force along end -> centre.
  ASSERT_TRUE(disc_wall_contact({0.3, 0.4}, 1.0, seg, c));
  EXPECT_NEAR(c.depth, 0.5, 1e-12);
  EXPECT_NEAR(c.normal.x, 0.6, 1e-12);
  EXPECT_NEAR(c.normal.y, 0.8, 1e-12);
}
