#include "velum/parallel/equation_layout.hpp"

#include <algorithm>
#include <cmath>

#include "velum/parallel/processes.hpp"

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
  // equations to send (in the order asked: ascending). Ghosts are ascending and the owners'
  // ranges in rank order: the ghosts come grouped by owner, in rank order.
  std::vector<std::vector<long>> ask(p);
  std::vector<int> receive_count(p, 0);
  for (size_t k = 0; k < ghosts_.size(); ++k) {
    const auto q = static_cast<size_t>(owner(ghosts_[k]));
    ask[q].push_back(ghosts_[k]);
    receive_.push_back(owned_ + static_cast<int>(k));
    ++receive_count[q];
  }
  const auto asked = processes::exchange(ask);  // once, at set-up: who reads what of whom
  int sent = 0, received = 0;
  for (size_t q = 0; q < p; ++q) {
    for (long g : asked[q]) send_.push_back(static_cast<int>(g - first_));
    const int n_send = static_cast<int>(asked[q].size());
    if (n_send > 0) to_readers_.push_back({static_cast<int>(q), sent, n_send});
    if (receive_count[q] > 0)
      from_owners_.push_back({static_cast<int>(q), received, receive_count[q]});
    sent += n_send;
    received += receive_count[q];
  }
  out_.resize(std::max(send_.size(), receive_.size()));
  in_.resize(out_.size());
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
  for (size_t k = 0; k < send_.size(); ++k) out_[k] = x[send_[k]];
  processes::exchange(out_.data(), to_readers_, in_.data(), from_owners_);
  for (size_t k = 0; k < receive_.size(); ++k) x[receive_[k]] = in_[k];
}

void EquationLayout::sum_to_owners(VecX& x) const {
  if (!distributed_) return;
  for (size_t k = 0; k < receive_.size(); ++k) out_[k] = x[receive_[k]];
  processes::exchange(out_.data(), from_owners_, in_.data(), to_readers_);
  // In rank order of the senders, after the owner's own part: the same bits on any run.
  for (size_t k = 0; k < send_.size(); ++k) x[send_[k]] += in_[k];
  update_ghosts(x);
}

VecX EquationLayout::gather_global(const VecX& x) const {
  if (!distributed_) return x;
  // Owned ranges are contiguous and in rank order: their concatenation is the global order.
  const std::vector<double> all =
      processes::gather(std::vector<double>(x.data(), x.data() + owned_));
  return Eigen::Map<const VecX>(all.data(), static_cast<Eigen::Index>(all.size()));
}

VecX EquationLayout::local_part(const VecX& whole) const {
  if (!distributed_) return whole;
  VecX x(local());
  for (int i = 0; i < local(); ++i) x[i] = whole[global(i)];
  return x;
}

}  // namespace velum
