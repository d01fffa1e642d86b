// Rigid meshes (shape: mesh): the signed distance of a box of twelve triangles against the
// box's closed form, inside and outside; its normal and curvature against central differences
// of the distance and the normal; the top face moved by a turn and a translation against the
// plane moved the same way; degenerate meshes refused; which bodies lie inside which (a bad
// model's check).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "load/rigid_mesh.hpp"
#include "velum/load/contact_load.hpp"

namespace velum {
namespace {

// The box [-1, 1] x [-1, 1] x [-1, 0], its faces' normals out of it.
RigidBody box_body() {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 0.0 : -1.0);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<std::array<int, 3>> t;
  for (const auto& q : quads) t.push_back({q[0], q[1], q[2]}), t.push_back({q[0], q[2], q[3]});
  RigidBody b;
  b.name = "box";
  b.shape = RigidBody::Shape::kMesh;
  b.point = Vec3(0, 0, -0.5);
  b.mesh = make_rigid_mesh(std::move(v), std::move(t));
  return b;
}

double box_distance(const Vec3& p) {
  const Vec3 q = (p - Vec3(0, 0, -0.5)).cwiseAbs() - Vec3(1, 1, 0.5);
  const double outside = q.cwiseMax(0.0).norm();
  return outside > 0 ? outside : q.maxCoeff();
}

TEST(RigidMesh, BoxDistanceNormalAndCurvature) {
  const RigidBody b = box_body();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  double worst_g = 0, worst_n = 0, worst_H = 0;
  int inside = 0, edges = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 x(u(rng), u(rng), u(rng) - 0.5);
    Vec3 n;
    Mat3 H;
    const double g = b.gap(x, 1.0, n, H);
    worst_g = std::max(worst_g, std::abs(g - box_distance(x)));
    inside += g < 0;
    edges += H.norm() > 0;
    if (std::abs(g) < 0.05) continue;  // central differences need the same region about x
    const double h = 1e-6;
    Vec3 dg;
    Mat3 dn;
    for (int c = 0; c < 3; ++c) {
      Vec3 np, nm;
      Mat3 Hp;
      const double gp = b.gap(x + h * Vec3::Unit(c), 1.0, np, Hp);
      const double gm = b.gap(x - h * Vec3::Unit(c), 1.0, nm, Hp);
      dg[c] = (gp - gm) / (2 * h);
      dn.col(c) = (np - nm) / (2 * h);
    }
    worst_n = std::max(worst_n, (dg - n).norm());
    const double eH = (dn - H).norm() / std::max(1.0, H.norm());
    worst_H = std::max(worst_H, eH);
  }
  std::cout << "box mesh: distance error " << worst_g << ", normal " << worst_n << ", curvature "
            << worst_H << " (" << inside << " of 400 inside, " << edges
            << " nearest an edge or a corner)\n";
  EXPECT_LT(worst_g, 1e-12);
  EXPECT_LT(worst_n, 1e-6);
  EXPECT_LT(worst_H, 1e-5);
  EXPECT_GT(inside, 10);
  EXPECT_GT(edges, 100);
}

TEST(RigidMesh, MovedTopFaceIsTheMovedPlane) {
  RigidBody box = box_body(), plane;
  plane.shape = RigidBody::Shape::kPlane;
  plane.point = Vec3::Zero();
  plane.direction = Vec3::UnitZ();
  for (RigidBody* b : {&box, &plane}) {
    b->rotation = Vec3(0.3, -0.2, 0.5);
    b->displacement = Vec3(0.1, 0.2, -0.3);
    b->pivot = Vec3(0.2, 0.1, 0.0);
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.8, 0.8), w(-0.15, 0.3);
  double worst = 0;
  for (int k = 0; k < 100; ++k) {
    const double s = 0.7;
    // A point over the top face's middle, in the moved body's frame.
    const Vec3 x = box.moved(Vec3(u(rng), u(rng), w(rng)), s);
    Vec3 n1, n2;
    Mat3 H1, H2;
    const double g1 = box.gap(x, s, n1, H1), g2 = plane.gap(x, s, n2, H2);
    worst = std::max({worst, std::abs(g1 - g2), (n1 - n2).norm(), (H1 - H2).norm()});
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(RigidMesh, DegenerateTriangleRefused) {
  std::vector<Vec3> v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  try {
    make_rigid_mesh(v, {{0, 1, 2}});
    FAIL() << "a degenerate triangle was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos);
  }
  EXPECT_THROW(make_rigid_mesh(v, {}), std::invalid_argument);
}

// A body inside another is bad input (the reader refuses it): spheres, a closed box and an
// open one, a plane's half-space.
TEST(RigidMesh, WhichBodyLiesInsideWhich) {
  const RigidBody box = box_body();  // [-1, 1] x [-1, 1] x [-1, 0]
  auto sphere = [](const Vec3& c, double r) {
    RigidBody s;
    s.shape = RigidBody::Shape::kSphere;
    s.point = c, s.radius = r;
    return s;
  };
  EXPECT_TRUE(box.mesh->closed());
  EXPECT_TRUE(sphere(Vec3(0, 0, -0.5), 0.4).lies_inside(box));
  EXPECT_FALSE(sphere(Vec3(0, 0, -0.5), 0.6).lies_inside(box));  // through the top and bottom
  EXPECT_FALSE(sphere(Vec3(0, 0, 1), 0.4).lies_inside(box));
  EXPECT_TRUE(box.lies_inside(sphere(Vec3(0, 0, -0.5), 1.6)));  // corners at 1.5
  EXPECT_FALSE(box.lies_inside(sphere(Vec3(0, 0, -0.5), 1.4)));
  EXPECT_FALSE(box.lies_inside(box));  // not strictly: its vertices are on it
  RigidBody floor;                     // the half-space z < 0.5
  floor.shape = RigidBody::Shape::kPlane;
  floor.point = Vec3(0, 0, 0.5), floor.direction = Vec3::UnitZ();
  EXPECT_TRUE(box.lies_inside(floor));
  EXPECT_TRUE(sphere(Vec3(0, 0, 0), 0.5).lies_inside(floor));
  EXPECT_FALSE(sphere(Vec3(0, 0, 0), 0.6).lies_inside(floor));
  EXPECT_FALSE(floor.lies_inside(box));  // unbounded
  // The box without its top: a side, not an inside.
  std::vector<Vec3> v = box.mesh->vertices();
  RigidBody open = box;
  std::vector<std::array<int, 3>> t = {{0, 2, 3}, {0, 3, 1}, {0, 1, 5}, {0, 5, 4}, {2, 6, 7},
                                       {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  open.mesh = make_rigid_mesh(v, t);
  EXPECT_FALSE(open.mesh->closed());
  EXPECT_FALSE(sphere(Vec3(0, 0, -0.5), 0.4).lies_inside(open));
}

}  // namespace
}  // namespace velum
