// The face tree (face_tree.hpp): children stored in pairs after their parent, so a reverse
// sweep over the nodes refits every child before its parent.
#include "face_tree.hpp"

#include <algorithm>

namespace velum::contact {

void FaceTree::build(std::span<const Box> boxes) {
  nodes_.clear();
  boxes_ = boxes;
  faces_.resize(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) faces_[i] = static_cast<int>(i);
  if (boxes.empty()) return;
  nodes_.reserve(2 * boxes.size() / kLeaf + 2);
  nodes_.emplace_back();
  split(boxes, 0, 0, static_cast<int>(boxes.size()), 1);
  built_volume_ = volume();
}

int FaceTree::split(std::span<const Box> boxes, int node, int begin, int end, int depth) {
  Box centres;
  Box all;
  for (int i = begin; i < end; ++i) {
    const Box& b = boxes[static_cast<size_t>(faces_[static_cast<size_t>(i)])];
    all.extend(b);
    centres.extend(b.center());
  }
  nodes_[static_cast<size_t>(node)].box = all;
  // Depth bounded by the stack of query(): a leaf may then hold more than kLeaf faces.
  if (end - begin <= kLeaf || depth + 2 >= kMaxDepth / 2) {
    nodes_[static_cast<size_t>(node)].first = begin;
    nodes_[static_cast<size_t>(node)].count = end - begin;
    return node;
  }
  int axis = 0;
  centres.sizes().maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(faces_.begin() + begin, faces_.begin() + mid, faces_.begin() + end,
                   [&](int a, int b) {
                     return boxes[static_cast<size_t>(a)].center()[axis] <
                            boxes[static_cast<size_t>(b)].center()[axis];
                   });
  const int left = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[static_cast<size_t>(node)].first = left;
  nodes_[static_cast<size_t>(node)].count = 0;
  split(boxes, left, begin, mid, depth + 1);
  split(boxes, left + 1, mid, end, depth + 1);
  return node;
}

void FaceTree::refit(std::span<const Box> boxes) {
  boxes_ = boxes;
  double v = 0;
  for (size_t k = nodes_.size(); k-- > 0;) {
    Node& n = nodes_[k];
    if (n.count > 0) {
      n.box.setEmpty();
      for (int i = n.first; i < n.first + n.count; ++i)
        n.box.extend(boxes[static_cast<size_t>(faces_[static_cast<size_t>(i)])]);
    } else {
      n.box = nodes_[static_cast<size_t>(n.first)].box;
      n.box.extend(nodes_[static_cast<size_t>(n.first + 1)].box);
    }
    v += n.box.isEmpty() ? 0.0 : n.box.sizes().prod();
  }
  // Faces that moved far apart from the ones they were grouped with (a fold swept through
  // the sheet) leave boxes that overlap more and more and queries that visit more of them:
  // built afresh once the boxes' volume has doubled since the last build.
  if (built_volume_ > 0 && v > kRebuildLooseness * built_volume_) {
    build(boxes);
    ++rebuilds_;
  }
}

double FaceTree::volume() const {
  double v = 0;
  for (const Node& n : nodes_) v += n.box.isEmpty() ? 0.0 : n.box.sizes().prod();
  return v;
}

}  // namespace velum::contact
