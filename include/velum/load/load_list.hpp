// The model's loads: one list of load objects in summing order (LoadOrder, then as given),
// copied deeply (clone), and typed views of it (Model::point_loads, ...) that read and add
// loads of one kind by their parameters.
#pragma once

#include <cstddef>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

class LoadList {
 public:
  LoadList() = default;
  LoadList(const LoadList& other);
  LoadList& operator=(const LoadList& other);
  LoadList(LoadList&&) noexcept = default;
  LoadList& operator=(LoadList&&) noexcept = default;
  ~LoadList();

  /// Adds a load after the others of its order (LoadOrder) and before the later ones.
  Load& add(std::unique_ptr<Load> load);
  /// Replaces load i by one of the same order (a held load).
  void replace(size_t i, std::unique_ptr<Load> load);
  /// Keeps the loads for which keep(load) is true, in order.
  template <class Keep>
  void keep_if(const Keep& keep) {
    std::vector<std::unique_ptr<Load>> kept;
    for (auto& l : items_)
      if (keep(*l)) kept.push_back(std::move(l));
    items_ = std::move(kept);
  }
  void clear() { items_.clear(); }

  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  Load& operator[](size_t i) { return *items_[i]; }
  const Load& operator[](size_t i) const { return *items_[i]; }
  auto begin() { return items_.begin(); }
  auto end() { return items_.end(); }
  auto begin() const { return items_.cbegin(); }
  auto end() const { return items_.cend(); }

 private:
  std::vector<std::unique_ptr<Load>> items_;
};

/// The loads counted by kind for a summary: "1 point, 0 edge, 2 pressure, 0 gravity" (those
/// four always, other kinds after them when present; see Load::counted_as).
std::string load_counts(const LoadList& loads);
/// The loads' own summary lines (Load::summary), in order.
std::vector<std::string> load_summaries(const LoadList& loads);

/// The loads of a list whose parameters are a `Params` (PointLoad, ...), in order, as
/// references to those parameters; push_back adds the load those parameters make
/// (make_load(Params), declared with each load's parameters).
template <class Params>
class LoadsOf {
 public:
  explicit LoadsOf(LoadList* all) : all_(all) {}
  LoadsOf(const LoadsOf&) = delete;
  LoadsOf& operator=(const LoadsOf&) = delete;

  void push_back(Params p) { all_->add(make_load(std::move(p))); }
  Params& emplace_back() {
    push_back(Params{});
    return back();
  }
  size_t size() const {
    size_t n = 0;
    for (const auto& l : *all_) n += dynamic_cast<const Params*>(l.get()) != nullptr;
    return n;
  }
  bool empty() const { return size() == 0; }
  Params& operator[](size_t i) const {
    for (const auto& l : *all_)
      if (auto* p = dynamic_cast<Params*>(l.get()); p && i-- == 0) return *p;
    throw std::out_of_range("no such load");
  }
  Params& at(size_t i) const { return (*this)[i]; }
  Params& front() const { return (*this)[0]; }
  Params& back() const { return (*this)[size() - 1]; }

  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Params;
    using difference_type = std::ptrdiff_t;
    using pointer = Params*;
    using reference = Params&;
    iterator(const LoadsOf* v, size_t i) : v_(v), i_(i) {}
    Params& operator*() const { return (*v_)[i_]; }
    Params* operator->() const { return &(*v_)[i_]; }
    iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator==(const iterator& o) const { return i_ == o.i_; }

   private:
    const LoadsOf* v_;
    size_t i_;
  };
  iterator begin() const { return {this, 0}; }
  iterator end() const { return {this, size()}; }

 private:
  LoadList* all_;
};

}  // namespace velum
