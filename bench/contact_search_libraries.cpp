// The sheet contact's search against what Debian offers for it (docs/contact.md, "Search"):
// the same evaluation (the faces' boxes moved, then one point query per node: the faces whose
// box holds the node) by Velum's own box tree (src/load/face_tree.hpp), Bullet's dynamic AABB
// tree (btDbvt, refitted leaf by leaf), FCL's dynamic AABB tree manager (objects updated),
// Embree's BVH over user geometry (refit build, point queries) and nanoflann's kd-tree of face
// centres (rebuilt, radius queries filtered by the boxes). Each answers the same number of
// candidates per node (the counter `found`): the comparison is of equal work.
// Built only where those libraries are installed (bench/CMakeLists.txt).
#include <benchmark/benchmark.h>
#include <bullet/BulletCollision/BroadphaseCollision/btDbvt.h>
#include <embree3/rtcore.h>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>
#include <cmath>
#include <memory>
#include <nanoflann.hpp>
#include <vector>

#include "load/face_tree.hpp"
#include "wavy_sheet.hpp"

namespace {

using velum::Vec3;
using velum::contact::Box;

using Sheet = velum::bench::WavySheet;

using velum::bench::wavy_sheet;

// Two sheets, alternated so every evaluation moves every face.
struct Pair {
  Sheet a, b;
  explicit Pair(long faces) : a(wavy_sheet(faces)), b(wavy_sheet(faces, 0.01)) {}
  const Sheet& at(long k) const { return k % 2 ? b : a; }
};

void report(benchmark::State& state, const Pair& p, long found) {
  benchmark::DoNotOptimize(found);
  state.counters["found"] =
      static_cast<double>(found) / static_cast<double>(state.iterations() * p.a.points.size());
  state.SetComplexityN(state.range(0));
}

void BM_OwnTree(benchmark::State& state) {
  const Pair p(state.range(0));
  velum::contact::FaceTree tree;
  tree.build(p.a.boxes);
  long found = 0, k = 0;
  for (auto _ : state) {
    const Sheet& s = p.at(++k);
    tree.refit(s.boxes);
    for (const Vec3& x : s.points) tree.query(x, [&](int) { ++found; });
  }
  report(state, p, found);
}

btDbvtVolume bullet_box(const Box& b) {
  return btDbvtVolume::FromMM(btVector3(b.min().x(), b.min().y(), b.min().z()),
                              btVector3(b.max().x(), b.max().y(), b.max().z()));
}

struct BulletCount : btDbvt::ICollide {
  long* found;
  void Process(const btDbvtNode*) override { ++*found; }
};

void BM_BulletDbvt(benchmark::State& state) {
  const Pair p(state.range(0));
  btDbvt tree;
  std::vector<btDbvtNode*> leaves;
  leaves.reserve(p.a.boxes.size());
  for (const Box& b : p.a.boxes) leaves.push_back(tree.insert(bullet_box(b), nullptr));
  tree.optimizeTopDown();
  long found = 0, k = 0;
  BulletCount count;
  count.found = &found;
  for (auto _ : state) {
    const Sheet& s = p.at(++k);
    for (size_t f = 0; f < leaves.size(); ++f) {
      btDbvtVolume v = bullet_box(s.boxes[f]);
      tree.update(leaves[f], v);
    }
    for (const Vec3& x : s.points) {
      const btVector3 q(x.x(), x.y(), x.z());
      tree.collideTV(tree.m_root, btDbvtVolume::FromMM(q, q), count);
    }
  }
  report(state, p, found);
}

using FclObject = fcl::CollisionObject<double>;

std::shared_ptr<fcl::Box<double>> fcl_shape(const Box& b) {
  const Vec3 d = b.sizes();
  return std::make_shared<fcl::Box<double>>(d.x(), d.y(), d.z());
}

void BM_FclDynamicAabbTree(benchmark::State& state) {
  const Pair p(state.range(0));
  std::vector<std::unique_ptr<FclObject>> objects;
  std::vector<FclObject*> raw;
  for (const Box& b : p.a.boxes) {
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.translation() = b.center();
    objects.push_back(std::make_unique<FclObject>(fcl_shape(b), tf));
    raw.push_back(objects.back().get());
  }
  fcl::DynamicAABBTreeCollisionManager<double> manager;
  manager.registerObjects(raw);
  manager.setup();
  // The query: a point-sized box at the node; FCL calls back once per overlapping AABB, and
  // the callback counts without a narrow phase.
  FclObject probe(std::make_shared<fcl::Box<double>>(1e-12, 1e-12, 1e-12));
  long found = 0, k = 0;
  auto count = [](FclObject*, FclObject*, void* data) {
    ++*static_cast<long*>(data);
    return false;
  };
  for (auto _ : state) {
    const Sheet& s = p.at(++k);
    for (size_t f = 0; f < raw.size(); ++f) {
      // The faces change size as they move: the object's box is set from the new one.
      raw[f]->setTranslation(s.boxes[f].center());
      static_cast<fcl::Box<double>*>(
          const_cast<fcl::CollisionGeometry<double>*>(raw[f]->collisionGeometry().get()))
          ->side = s.boxes[f].sizes();
      raw[f]->computeAABB();
    }
    manager.update();
    for (const Vec3& x : s.points) {
      probe.setTranslation(x);
      probe.computeAABB();
      manager.collide(&probe, &found, count);
    }
  }
  report(state, p, found);
}

struct EmbreeFaces {
  const std::vector<Box>* boxes;
};

void embree_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* faces = static_cast<const EmbreeFaces*>(args->geometryUserPtr);
  const Box& b = (*faces->boxes)[args->primID];
  args->bounds_o->lower_x = static_cast<float>(b.min().x());
  args->bounds_o->lower_y = static_cast<float>(b.min().y());
  args->bounds_o->lower_z = static_cast<float>(b.min().z());
  args->bounds_o->upper_x = static_cast<float>(b.max().x());
  args->bounds_o->upper_y = static_cast<float>(b.max().y());
  args->bounds_o->upper_z = static_cast<float>(b.max().z());
}

struct EmbreeQuery {
  const std::vector<Box>* boxes;
  Vec3 x;
  long* found;
};

bool embree_visit(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<EmbreeQuery*>(args->userPtr);
  // Embree's bounds are single precision: the box test in double decides, as ours does.
  if ((*q->boxes)[args->primID].contains(q->x)) ++*q->found;
  return false;
}

void BM_EmbreeBvh(benchmark::State& state) {
  const Pair p(state.range(0));
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_REFIT);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  EmbreeFaces faces{&p.a.boxes};
  rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(p.a.boxes.size()));
  rtcSetGeometryUserData(geometry, &faces);
  rtcSetGeometryBoundsFunction(geometry, embree_bounds, nullptr);
  rtcSetGeometryPointQueryFunction(geometry, embree_visit);
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_REFIT);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcCommitScene(scene);
  long found = 0, k = 0;
  for (auto _ : state) {
    const Sheet& s = p.at(++k);
    faces.boxes = &s.boxes;
    rtcCommitGeometry(geometry);  // the bounds have changed: refit
    rtcCommitScene(scene);
    EmbreeQuery q{&s.boxes, Vec3::Zero(), &found};
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    for (const Vec3& x : s.points) {
      RTCPointQuery query;
      query.x = static_cast<float>(x.x());
      query.y = static_cast<float>(x.y());
      query.z = static_cast<float>(x.z());
      query.radius = 0.0f;
      query.time = 0.0f;
      q.x = x;
      rtcPointQuery(scene, &query, &context, nullptr, &q);
    }
  }
  rtcReleaseGeometry(geometry);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  report(state, p, found);
}

// nanoflann's adaptor: the face boxes' centres.
struct Centres {
  const std::vector<Box>* boxes;
  size_t kdtree_get_point_count() const { return boxes->size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return (*boxes)[i].center()[d]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Centres>,
                                                   Centres, 3, unsigned>;

void BM_NanoflannKdTree(benchmark::State& state) {
  const Pair p(state.range(0));
  long found = 0, k = 0;
  std::vector<std::pair<unsigned, double>> hits;
  for (auto _ : state) {
    const Sheet& s = p.at(++k);
    // A kd-tree of points has no refit: rebuilt every evaluation. A face's box holds x only
    // if its centre lies within the largest half-diagonal of x.
    Centres centres{&s.boxes};
    KdTree tree(3, centres, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    double half = 0;
    for (const Box& b : s.boxes) half = std::max(half, 0.5 * b.sizes().norm());
    const nanoflann::SearchParams params(32, 0, false);
    for (const Vec3& x : s.points) {
      hits.clear();
      tree.radiusSearch(x.data(), half * half, hits, params);
      for (const auto& h : hits) found += s.boxes[h.first].contains(x);
    }
  }
  report(state, p, found);
}

#define VELUM_SEARCH_SIZES ->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)
BENCHMARK(BM_OwnTree) VELUM_SEARCH_SIZES->Complexity();
BENCHMARK(BM_BulletDbvt) VELUM_SEARCH_SIZES->Complexity();
BENCHMARK(BM_FclDynamicAabbTree) VELUM_SEARCH_SIZES->Complexity();
BENCHMARK(BM_EmbreeBvh) VELUM_SEARCH_SIZES->Complexity();
BENCHMARK(BM_NanoflannKdTree) VELUM_SEARCH_SIZES->Complexity();

}  // namespace
