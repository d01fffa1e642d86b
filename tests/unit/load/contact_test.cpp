// Contact with rigid bodies: the node law's derivative against central differences for each
// surface (moved and turned), frictionless, sticking and slipping; the term's matrix in a
// system (frames, eliminated components) against the same; and a node pressed onto a plane
// with the multiplier updated at accepted steps.
#include <gtest/gtest.h>

#include <iostream>

#include "../../verification/model_builders.hpp"
#include "load/contact_law.hpp"
#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"

namespace velum {
namespace {

RigidBody body_of(int shape) {
  RigidBody b;
  b.shape = static_cast<RigidBody::Shape>(shape);
  b.point = Vec3(0.1, -0.2, 0.05);
  b.direction = Vec3(0.2, 0.1, 1).normalized();
  b.radius = 0.7;
  b.displacement = Vec3(0.05, 0.02, -0.1);
  b.rotation = Vec3(0.1, -0.3, 0.2);
  b.pivot = Vec3(0.3, 0.1, 0);
  return b;
}

// The force on a node at x against body b moved by s (anchor A at s = 0); with damping c, at
// velocity v relative to the body.
contact::NodeResult force(const RigidBody& b, double s, const Vec3& x, const Vec3& A, double mu,
                          bool tangent, double c = 0, const Vec3& v = Vec3::Zero()) {
  contact::NodeInput in;
  in.g = b.gap(x, s, in.n, in.H) - 0.01;
  in.w = x - b.moved(A, s);
  in.lambda = 3.0;
  in.k = 1e3;
  in.mu = mu;
  in.c = c;
  in.v = v;
  return contact::node_force(in, tangent);
}

// A point of body b moved by s just inside its surface (on it along its normal n, 2e-3 deep).
Vec3 just_inside(const RigidBody& b, double s, Vec3& n) {
  Mat3 H;
  Vec3 x = b.moved(b.point + Vec3(0.3, 0.4, 0.2), s);
  x -= (b.gap(x, s, n, H) + 2e-3) * n;
  return x;
}

TEST(Contact, NodeLawMatchesFiniteDifferences) {
  const double s = 0.6;
  for (int shape = 0; shape < 3; ++shape) {
    const RigidBody b = body_of(shape);
    Vec3 n;
    Mat3 H;
    const Vec3 x = just_inside(b, s, n);
    ASSERT_NEAR(b.gap(x, s, n, H), -2e-3, 1e-12);
    // Anchors near (stick) and far (slip) along the surface.
    const Vec3 t = n.unitOrthogonal();
    for (int kind = 0; kind < 3; ++kind) {
      const double mu = kind == 0 ? 0.0 : 0.3;
      const Vec3 A = b.unmoved(x + (kind == 2 ? 0.01 : 1e-4) * t + 0.3e-4 * n.cross(t), s);
      const contact::NodeResult r = force(b, s, x, A, mu, true);
      ASSERT_NE(r.status, contact::Status::kOpen);
      if (kind > 0) {
        EXPECT_EQ(r.status, kind == 1 ? contact::Status::kStick : contact::Status::kSlip);
      }
      Mat3 fd;
      const double h = 1e-7;
      for (int c = 0; c < 3; ++c) {
        Vec3 e = Vec3::Zero();
        e[c] = h;
        fd.col(c) =
            (force(b, s, x + e, A, mu, false).f - force(b, s, x - e, A, mu, false).f) / (2 * h);
      }
      const double err = (r.D - fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
      std::cout << "shape " << shape << " kind " << kind << ": relative error " << err << "\n";
      EXPECT_LT(err, 1e-6) << shape << " " << kind;
      // The normal force is λ − k g, the tangential one within the cone.
      EXPECT_NEAR(r.p, 3.0 + 1e3 * (2e-3 + 0.01), 1e-9);
      EXPECT_LE((r.f - r.p * n).norm(), (mu + 1e-12) * r.p);
    }
  }
}

// The damped law (c > 0): the normal force λ − k g − c n·v, and both derivatives, ∂f/∂x (the
// normal turns under the velocity) and ∂f/∂v, against central differences on every surface,
// frictionless, sticking and slipping; a node leaving faster than the damping lets the
// penalty push is apart.
TEST(Contact, DampedNodeLawMatchesFiniteDifferences) {
  const double s = 0.6;
  for (int shape = 0; shape < 3; ++shape) {
    const RigidBody b = body_of(shape);
    Vec3 n;
    const Vec3 x = just_inside(b, s, n);
    const Vec3 t = n.unitOrthogonal();
    // Approaching, with a sliding part: the damping adds to the push.
    const Vec3 v = -0.05 * n + 0.3 * t - 0.2 * n.cross(t);
    for (int kind = 0; kind < 3; ++kind) {
      const double mu = kind == 0 ? 0.0 : 0.3;
      const Vec3 A = b.unmoved(x + (kind == 2 ? 0.01 : 1e-4) * t + 0.3e-4 * n.cross(t), s);
      const contact::NodeResult r = force(b, s, x, A, mu, true, 40.0, v);
      ASSERT_NE(r.status, contact::Status::kOpen);
      if (kind > 0) {
        EXPECT_EQ(r.status, kind == 1 ? contact::Status::kStick : contact::Status::kSlip);
      }
      EXPECT_NEAR(r.p, 3.0 + 1e3 * (2e-3 + 0.01) + 40.0 * 0.05, 1e-9);
      Mat3 fd, fdv;
      const double h = 1e-7;
      for (int c = 0; c < 3; ++c) {
        Vec3 e = Vec3::Zero();
        e[c] = h;
        fd.col(c) = (force(b, s, x + e, A, mu, false, 40.0, v).f -
                     force(b, s, x - e, A, mu, false, 40.0, v).f) /
                    (2 * h);
        fdv.col(c) = (force(b, s, x, A, mu, false, 40.0, v + e).f -
                      force(b, s, x, A, mu, false, 40.0, v - e).f) /
                     (2 * h);
      }
      const double err = (r.D - fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
      const double errv = (r.Dv - fdv).cwiseAbs().maxCoeff() / fdv.cwiseAbs().maxCoeff();
      std::cout << "damped, shape " << shape << " kind " << kind << ": relative errors " << err
                << " (position), " << errv << " (velocity)\n";
      EXPECT_LT(err, 1e-6) << shape << " " << kind;
      EXPECT_LT(errv, 1e-6) << shape << " " << kind;
      EXPECT_LE((r.f - r.p * n).norm(), (mu + 1e-12) * r.p);
    }
    // Leaving at 1 m/s: −c n·v = −40 N against an elastic push of 15 N: no force.
    const Vec3 A = b.unmoved(x, s);
    EXPECT_EQ(force(b, s, x, A, 0.3, true, 40.0, n).status, contact::Status::kOpen);
    EXPECT_EQ(force(b, s, x, A, 0.3, true, 40.0, n).f, Vec3::Zero());
  }
}

// A 3 x 3 quad4 sheet held at its edges, above a sphere it is pushed onto.
// `spin`: a free ball that rotates too; `twice`: two contact entries, each the set against the
// ball (`twice` false with `spin`: one entry of twice the penalty, the same forces).
// `relax`: the contact's relax_steps (the middle nodes start inside the ball).
std::unique_ptr<Model> sheet_on_sphere(double mu, bool free = false, bool spin = false,
                                       bool twice = false, int relax = 0, double damping = 0) {
  auto m = std::make_unique<Model>();
  test::NodeCache nodes(*m, 1e-9);
  std::vector<int> conn;
  test::mesh_patch(
      nodes, [](double u, double v) { return Vec3(u - 0.5, v - 0.5, 0.0); }, 3, 3, "quad4", conn);
  test::add_membrane(
      *m, "quad4", std::move(conn),
      SheetLaw(PlaneStressLaw::isotropic("iso", 1e9, 0.3)).with_prestress({1e6, 1e6, 0}), 1000.0,
      1e-3);
  m->fixed.push_back({test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.x()) > 0.49; }),
                      {true, true, true}});
  m->symmetry.push_back(
      {test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.y()) > 0.49; }), Vec3(0, 1, 0)});
  ContactLoad cl;
  cl.body.shape = RigidBody::Shape::kSphere;
  cl.body.point = Vec3(0.05, 0.02, -0.6);
  cl.body.radius = 0.65;  // some middle nodes are inside by up to 2 cm
  cl.friction = mu;
  cl.relax_steps = relax;
  cl.damping = damping;
  cl.parts.push_back({0, {0, 1, 2, 3, 4, 5, 6, 7, 8}});
  if (free) {  // the ball's node, with its mass
    cl.body_node = m->add_node(1000, cl.body.point);
    m->masses.push_back({cl.body_node, 5.0});
  }
  if (spin) {
    cl.body.inertia = 0.4 * 5.0 * 0.65 * 0.65 * Mat3::Identity();
    cl.body.angular_velocity = Vec3(0.3, -2.0, 0.5);
  }
  if (twice) {
    ContactLoad other = cl;
    other.index = 1;
    m->loads.add(make_load(other));
  } else if (spin) {
    cl.penalty_scale = 2;
  }
  m->loads.add(make_load(cl));
  for (auto& l : m->loads) l->set_up(*m);
  return m;
}

TEST(Contact, TermMatrixMatchesFiniteDifferences) {
  for (int kind = 0; kind < 4; ++kind) {
    const double mu = kind % 2 ? 0.4 : 0.0;
    const bool free = kind >= 2;
    auto m = sheet_on_sphere(mu, free);
    MechanicalSystem sys(*m);
    const int n = sys.size();
    std::srand(3);
    VecX u0 = 2e-3 * VecX::Random(n);
    // Anchors where the sheet was at u0, then a move that leaves some nodes sticking and
    // others slipping.
    sys.start_loads(0, u0, VecX::Zero(n));
    const VecX u = u0 + 1e-2 * VecX::Random(n);
    MatX J;
    const VecX f = term_forces(sys, 0, u, &J);
    ASSERT_GT(f.norm(), 0);
    const double err = term_matrix_error(sys, 0, u, J, 1e-8);
    std::cout << "friction " << mu << (free ? ", free ball" : "") << ": relative error " << err
              << "\n";
    EXPECT_LT(err, 1e-5) << kind;
    if (free) {  // the ball takes the opposite of the sheet's forces: they sum to zero
      NodePositions Fn = NodePositions::Zero(3, m->num_nodes());
      sys.dofs().scatter(f, Fn);
      EXPECT_LT(Fn.rowwise().sum().norm(), 1e-9 * f.norm());
    }
  }
}

// A damped contact in a system: the velocity Jacobian the system adds (cv ∂(−f)/∂v at the
// nodes in touch) against central differences of the residual in the velocities, frictionless
// and with friction (some nodes sticking, some slipping).
TEST(Contact, DampedTermVelocityJacobianMatchesFiniteDifferences) {
  for (const double mu : {0.0, 0.4}) {
    auto m = sheet_on_sphere(mu, false, false, false, 0, 0.3);
    MechanicalSystem sys(*m);
    const int n = sys.size();
    std::srand(5);
    const VecX u0 = 2e-3 * VecX::Random(n);
    sys.start_loads(0, u0, VecX::Zero(n));
    const VecX u = u0 + 1e-2 * VecX::Random(n), a = VecX::Zero(n);
    const VecX v = 0.05 * VecX::Random(n);
    VecX r;
    SparseMatrix J1, J0;
    sys.evaluate(0, u, v, a, 1.0, 1.0, 0.0, r, &J1);
    sys.evaluate(0, u, v, a, 1.0, 0.0, 0.0, r, &J0);
    const MatX Jv = MatX(J1) - MatX(J0);
    ASSERT_GT(Jv.cwiseAbs().maxCoeff(), 0);
    MatX fd(n, n);
    const double h = 1e-7;
    for (int k = 0; k < n; ++k) {
      VecX e = VecX::Zero(n), rp, rm;
      e[k] = h;
      sys.evaluate(0, u, v + e, a, 1.0, 0.0, 0.0, rp, nullptr);
      sys.evaluate(0, u, v - e, a, 1.0, 0.0, 0.0, rm, nullptr);
      fd.col(k) = (rp - rm) / (2 * h);
    }
    const double err = (Jv - fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
    std::cout << "damped, friction " << mu << ": velocity Jacobian relative error " << err << "\n";
    EXPECT_LT(err, 1e-6) << mu;
  }
}

// A checkpoint taken while the initial penetrations into a rigid body are being relaxed
// carries their offsets and count: a system restored from it has the forces of the one that
// saved it (not the whole overlap's), and reports the same initial penetrations.
TEST(Contact, RelaxationOffsetsGoThroughTheSavedState) {
  auto relaxed = sheet_on_sphere(0.0, false, false, false, 4);
  MechanicalSystem a(*relaxed), b(*relaxed);
  const VecX zero = VecX::Zero(a.size());
  VecX ra, rb;
  residuals_after_restore(a, b, ra, rb);
  ASSERT_GT(ra.norm(), 0);
  EXPECT_LT((ra - rb).norm(), 1e-12 * ra.norm());
  // One accepted step later (a quarter of the offsets relaxed more): the restored system
  // counts the steps from the same place.
  {
    MechanicalSystem a1(*relaxed), b1(*relaxed);
    VecX ra1, rb1;
    residuals_after_restore(a1, b1, ra1, rb1, 1);
    EXPECT_GT((ra1 - ra).norm(), 1e-3 * ra.norm());  // the step moved the offsets
    EXPECT_LT((ra1 - rb1).norm(), 1e-12 * ra1.norm());
  }
  // The count and the deepest (the penetration ratio before them is the last accepted
  // state's, which a restored system has not evaluated yet, and the peak after them is not
  // carried by checkpoints).
  auto initial = [](const MechanicalSystem& sys) {
    const std::string json = sys.loads()[0]->account_json();
    const size_t from = json.find("\"initial_penetrations\"");
    return json.substr(from, json.find(", \"peak_penetration_ratio\"") - from);
  };
  EXPECT_EQ(initial(b), initial(a));
  EXPECT_EQ(initial(a).find("\"initial_penetrations\": 0"), std::string::npos) << initial(a);
  // Pushed out at once, the same overlap gives a larger force: the offsets matter here.
  auto at_once = sheet_on_sphere(0.0);
  MechanicalSystem c(*at_once);
  c.start_loads(0.0, zero, zero);
  VecX rc;
  c.evaluate(0.0, zero, zero, zero, 1, 0, 0, rc, nullptr);
  std::cout << "sheet on a ball, relaxed over 4 steps: residual " << ra.norm()
            << ", pushed out at once " << rc.norm() << "\n";
  EXPECT_GT(rc.norm(), 1.5 * ra.norm());
}

// A rotating free ball in two contact entries with the sheet of sheet_on_sphere (the same set
// twice) turns as in one entry of twice the penalty (the same forces): one rotation, turned by
// the sum of both entries' moments (a rotation each would see half); the first entry saves
// it, and a system restored from the saved state goes on from where the saver left it.
TEST(Contact, RotatingBodyInTwoEntriesSharesItsRotation) {
  auto one = sheet_on_sphere(0.4, true, true), two = sheet_on_sphere(0.4, true, true, true);
  MechanicalSystem a(*one), b(*two);
  const int n = a.size();
  ASSERT_EQ(b.size(), n);
  std::srand(11);
  VecX u = 2e-3 * VecX::Random(n);
  a.start_loads(0, u, VecX::Zero(n));
  b.start_loads(0, u, VecX::Zero(n));
  for (int k = 1; k <= 5; ++k) {  // accepted states with the sheet moving under the ball
    u += 1e-3 * VecX::Random(n);
    a.accept(0.01 * k, u, VecX::Zero(n));
    b.accept(0.01 * k, u, VecX::Zero(n));
  }
  const NodePositions x = one->X + a.displacements(0.05, u);
  const auto w = [&](const MechanicalSystem& s, int c) {
    return *s.loads()[0]->quantity_at(fmt::format("rigid_angular_velocity:{}:{}", "", c), 0.05, x);
  };
  const Vec3 wa(w(a, 0), w(a, 1), w(a, 2)), wb(w(b, 0), w(b, 1), w(b, 2));
  std::cout << "rotating ball: angular velocity after 5 steps " << wa.transpose()
            << " (one entry), difference with two entries " << (wa - wb).norm() << "\n";
  EXPECT_GT((wa - Vec3(0.3, -2.0, 0.5)).norm(), 1e-3);  // the moments turned it
  EXPECT_LT((wa - wb).norm(), 1e-12 * wa.norm());
  // The kinetic energy counted once (by the first entry).
  EXPECT_NEAR(b.load_kinetic_energy(), a.load_kinetic_energy(), 1e-12);
  EXPECT_EQ(b.loads()[1]->kinetic_energy(), 0.0);
  // Saved and restored: the next step's residual is the saver's.
  MechanicalSystem c(*two);
  c.restore_load_state(b.save_load_state());
  VecX rb, rc;
  const VecX zero = VecX::Zero(n);
  b.evaluate(0.06, u, zero, zero, 1, 0, 0, rb, nullptr);
  c.evaluate(0.06, u, zero, zero, 1, 0, 0, rc, nullptr);
  ASSERT_GT(rb.norm(), 0);
  EXPECT_LT((rb - rc).norm(), 1e-12 * rb.norm());
}

}  // namespace
}  // namespace velum
