#include "velum/load/load_list.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace velum {

LoadList::LoadList(const LoadList& other) {
  items_.reserve(other.items_.size());
  for (const auto& l : other.items_) items_.push_back(l->clone());
}

LoadList& LoadList::operator=(const LoadList& other) {
  if (this != &other) *this = LoadList(other);
  return *this;
}

LoadList::~LoadList() = default;

Load& LoadList::add(std::unique_ptr<Load> load) {
  const LoadOrder order = load->order();
  const auto at =
      std::find_if(items_.begin(), items_.end(), [&](const auto& l) { return l->order() > order; });
  return **items_.insert(at, std::move(load));
}

void LoadList::replace(size_t i, std::unique_ptr<Load> load) {
  if (load->order() != items_[i]->order())
    throw std::logic_error("a load replaced by one of another order");
  items_[i] = std::move(load);
}

std::string load_counts(const LoadList& loads) {
  std::vector<std::pair<std::string_view, int>> counts = {
      {"point", 0}, {"edge", 0}, {"pressure", 0}, {"gravity", 0}};
  for (const auto& l : loads) {
    const std::string_view as = l->counted_as();
    if (as.empty()) continue;
    auto it =
        std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == as; });
    if (it == counts.end()) it = counts.insert(counts.end(), {as, 0});
    ++it->second;
  }
  std::string out;
  for (const auto& [kind, n] : counts)
    out += fmt::format("{}{} {}", out.empty() ? "" : ", ", n, kind);
  return out;
}

std::vector<std::string> load_summaries(const LoadList& loads) {
  std::vector<std::string> lines;
  std::map<std::string_view, int> index;
  for (const auto& l : loads)
    if (std::string line = l->summary(index[l->kind()]++); !line.empty())
      lines.push_back(std::move(line));
  return lines;
}

void restrict_nodes(std::vector<int>& nodes, const std::vector<int>& local_of) {
  std::vector<int> kept;
  for (int n : nodes)
    if (const int l = local_of[static_cast<size_t>(n)]; l >= 0) kept.push_back(l);
  nodes = std::move(kept);
}

}  // namespace velum
