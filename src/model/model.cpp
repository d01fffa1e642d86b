#include "velum/model/model.hpp"

#include <stdexcept>

namespace velum {

int Model::add_node(long id, const Vec3& x) {
  if (node_index.count(id)) throw std::invalid_argument("duplicate node id " + std::to_string(id));
  const int i = num_nodes();
  X.conservativeResize(3, i + 1);
  X.col(i) = x;
  node_ids.push_back(id);
  node_index[id] = i;
  return i;
}

int Model::num_elements() const {
  int n = 0;
  for (const auto& b : blocks) n += b->size();
  return n;
}

}  // namespace velum
