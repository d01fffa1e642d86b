#include "velum/assembly/equation_layout.hpp"

#include <algorithm>
#include <cmath>

#include "velum/solve/processes.hpp"

namespace velum {

EquationLayout::EquationLayout(std::vector<long> row_start, std::vector<long> ghosts)
    : distributed_(processes::count() > 1),
      row_start_(std::move(row_start)),
      ghosts_(std::move(ghosts)) {
  const auto rank = static_cast<size_t>(processes::rank());
  const auto p = static_cast<size_t>(processes::count());
  first_ = row_start_[rank];
  owned_ = static_cast<int>(row_start_[rank + 1] - first_);
  total_ = row_start_.back();
  // Each ghost is asked of its owner; the owner keeps, per asking process, which of its
  // equations to send (in the order asked: ascending).
  receive_.assign(p, {});
  std::vector<std::vector<long>> ask(p);
  for (size_t k = 0; k < ghosts_.size(); ++k) {
    const auto q = static_cast<size_t>(owner(ghosts_[k]));
    ask[q].push_back(ghosts_[k]);
    receive_[q].push_back(owned_ + static_cast<int>(k));
  }
  const auto asked = processes::exchange(ask);
  send_.assign(p, {});
  for (size_t q = 0; q < p; ++q)
    for (long g : asked[q]) send_[q].push_back(static_cast<int>(g - first_));
}

int EquationLayout::owner(long g) const {
  return static_cast<int>(std::upper_bound(row_start_.begin(), row_start_.end(), g) -
                          row_start_.begin()) -
         1;
}

int EquationLayout::local_of(long g) const {
  if (g >= first_ && g < first_ + owned_) return static_cast<int>(g - first_);
  const auto it = std::lower_bound(ghosts_.begin(), ghosts_.end(), g);
  return it != ghosts_.end() && *it == g ? owned_ + static_cast<int>(it - ghosts_.begin()) : -1;
}

double EquationLayout::dot(const VecX& a, const VecX& b) const {
  if (!distributed_) return a.dot(b);
  double s = a.head(owned_).dot(b.head(owned_));
  processes::sum(&s, 1);
  return s;
}

double EquationLayout::norm(const VecX& a) const {
  return distributed_ ? std::sqrt(dot(a, a)) : a.norm();
}

void EquationLayout::update_ghosts(VecX& x) const {
  if (!distributed_) return;
  std::vector<std::vector<double>> out(send_.size());
  for (size_t q = 0; q < send_.size(); ++q)
    for (int i : send_[q]) out[q].push_back(x[i]);
  const auto in = processes::exchange(out);
  for (size_t q = 0; q < receive_.size(); ++q)
    for (size_t k = 0; k < receive_[q].size(); ++k) x[receive_[q][k]] = in[q][k];
}

void EquationLayout::sum_to_owners(VecX& x) const {
  if (!distributed_) return;
  std::vector<std::vector<double>> out(receive_.size());
  for (size_t q = 0; q < receive_.size(); ++q)
    for (int i : receive_[q]) out[q].push_back(x[i]);
  const auto in = processes::exchange(out);
  for (size_t q = 0; q < send_.size(); ++q)
    for (size_t k = 0; k < send_[q].size(); ++k) x[send_[q][k]] += in[q][k];
  update_ghosts(x);
}

VecX EquationLayout::gather_global(const VecX& x) const {
  if (!distributed_) return x;
  // Owned ranges are contiguous and in rank order: the concatenation is the global order.
  std::vector<std::vector<double>> out(static_cast<size_t>(processes::count()));
  out[0].assign(x.data(), x.data() + owned_);
  const auto in = processes::exchange(out);
  VecX whole;
  if (processes::rank() == 0) {
    whole.resize(total_);
    for (size_t q = 0; q < in.size(); ++q)
      std::copy(in[q].begin(), in[q].end(), whole.data() + row_start_[q]);
  }
  return whole;
}

VecX EquationLayout::scatter_global(const VecX& whole) const {
  if (!distributed_) return whole;
  std::vector<std::vector<double>> out(static_cast<size_t>(processes::count()));
  if (processes::rank() == 0)
    for (size_t q = 0; q < out.size(); ++q)
      out[q].assign(whole.data() + row_start_[q], whole.data() + row_start_[q + 1]);
  const auto in = processes::exchange(out);
  VecX x(local());
  std::copy(in[0].begin(), in[0].end(), x.data());
  update_ghosts(x);
  return x;
}

}  // namespace velum
