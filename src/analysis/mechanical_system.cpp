#include "velum/analysis/mechanical_system.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "velum/math/threads.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {
namespace {

std::vector<long> node_ids_of(const Model& m, const ElementBlock& b, int e) {
  std::vector<long> ids;
  for (int n : b.nodes(e)) ids.push_back(m.node_ids[n]);
  return ids;
}

// Whether some entry is not zero (or not a number), in one pass shared between the threads.
bool any_nonzero(const VecX& x) {
  return parallel_sum(x.size(), [&](long first, long last) {
           for (long i = first; i < last; ++i)
             if (x[i] != 0) return 1.0;
           return 0.0;
         }) != 0;
}

}  // namespace

MechanicalSystem::MechanicalSystem(const Model& model)
    : model_(model), dofs_(model), assembler_(model, dofs_) {
  assembler_.mass(nullptr, &lumped_nodes_);
  lumped_eq_.setZero(size());
  equation_node_.assign(size(), 0);
  VecX X_eq = VecX::Zero(size());
  for (int n = 0; n < model.num_nodes(); ++n)
    for (int c = 0; c < 3; ++c)
      if (const int eq = dofs_.equation(n, c); eq >= 0) {
        lumped_eq_[eq] = lumped_nodes_[n];
        equation_node_[eq] = n;
        X_eq[eq] = model.X(c, n);
      }
  reference_position_norm_ = norm(X_eq);
  // Every load bound to this assembler, in the model's order (the order of the sum).
  const LoadSite site{model, assembler_, dofs_};
  for (const auto& load : model.loads) {
    terms_.push_back(load->bind(site));
    low_rank_columns_ += terms_.back()->low_rank_columns();
    velocity_ = velocity_ || terms_.back()->uses_velocity();
  }
  std::vector<LoadTerm*> all;
  for (const auto& term : terms_) all.push_back(term.get());
  for (size_t i = 0; i < terms_.size(); ++i) terms_[i]->connect(all, static_cast<int>(i));
  for (const PointMass& m : model.masses)
    if (m.drag_rho != 0 || m.drag_cd_area != 0)
      throw std::invalid_argument(
          "a point mass's drag is a load: give it as a DragLoad (Model::drag), not in PointMass");
  U_.setZero(3, model.num_nodes());
  external_reusable_ = !velocity_ && low_rank_columns_ == 0 && model.prescribed.empty();
  for (const auto& term : terms_) {
    std::vector<double> state;
    term->save_state(state);
    external_reusable_ = external_reusable_ && state.empty();
  }
  // Sections that change in time (reefing) book their work from the nodal arrays each step.
  for (const auto& blk : model.blocks)
    external_reusable_ = external_reusable_ && !blk->changes_in_time();
}

const SparseMatrix& MechanicalSystem::mass_matrix() const {
  if (!have_mass_) {
    assembler_.make_matrix(M_);
    assembler_.mass(&M_, nullptr);
    for (Eigen::Index n = 0; n < added_nodes_.size(); ++n)
      for (int c = 0; c < 3; ++c)
        if (const int eq = dofs_.equation(static_cast<int>(n), c); eq >= 0 && added_nodes_[n] != 0)
          M_.coeffRef(eq, eq) += added_nodes_[n];
    // The mass couples a node's components with the same component of its neighbours only
    // (ρ h ∫ N_a N_b dA times the identity): six of the nine entries of a block are zeros the
    // Jacobian's pattern holds. Its products walk the entries alone, the same sums (a zero
    // term adds nothing) over a third of the pattern.
    M_entries_ = M_;
    M_entries_.prune([](Eigen::Index, Eigen::Index, double v) { return v != 0.0; });
    have_mass_ = true;
  }
  return M_;
}

void MechanicalSystem::add_node_mass(const VecX& per_node) {
  if (distributed()) throw std::invalid_argument("mass scaling runs on one process only");
  if (added_nodes_.size() == 0) added_nodes_.setZero(model_.num_nodes());
  added_nodes_ += per_node;
  lumped_nodes_ += per_node;
  for (int eq = 0; eq < size(); ++eq) lumped_eq_[eq] = lumped_nodes_[equation_node_[eq]];
  have_mass_ = false;  // rebuilt with it on next use
}

const SparseMatrix& MechanicalSystem::mass_entries() const {
  mass_matrix();
  return M_entries_;
}

VecX MechanicalSystem::mass_times(const VecX& v) const {
  VecX Mv = mass_entries() * v;
  complete(Mv);
  return Mv;
}

void MechanicalSystem::complete(VecX& from_jacobian) const {
  dofs_.layout().sum_to_owners(from_jacobian);
}

double MechanicalSystem::sum_over_processes(double local) const {
  if (distributed()) processes::sum(&local, 1);
  return local;
}

void MechanicalSystem::sum_over_processes(double* values, long n) const {
  if (distributed()) processes::sum(values, n);
}

double MechanicalSystem::max_over_processes(double local) const {
  return distributed() ? processes::max(local) : local;
}

VecX MechanicalSystem::to_global(const VecX& x) const {
  return dofs_.layout().gather_global(x);
}

VecX MechanicalSystem::to_local(const VecX& whole) const {
  return dofs_.layout().local_part(whole);
}

double MechanicalSystem::global_entry(const VecX& x, int eq) const {
  if (!distributed()) return x[eq];
  const int i = dofs_.layout().local_of(eq);
  return sum_over_processes(i >= 0 && i < owned_size() ? x[i] : 0.0);
}

double MechanicalSystem::distributed_force_scale() {
  // The one-process norms of the summed internal and external forces: the shares completed at
  // the nodes two processes share, then each node counted by the process keeping it.
  const std::pair<double*, int> parts[] = {{Fint_.data(), 3}, {Fext_.data(), 3}};
  assembler_.sum_at_shared_nodes(parts);
  double sums[2] = {0, 0};
  for (int n = 0; n < model_.num_nodes(); ++n)
    if (assembler_.keeps_node(n)) {
      sums[0] += Fint_.col(n).squaredNorm();
      sums[1] += Fext_.col(n).squaredNorm();
    }
  processes::sum(sums, 2);
  return std::max({std::sqrt(sums[0]), std::sqrt(sums[1]), norm(mv_)});
}

void MechanicalSystem::apply_prescribed(double t, NodePositions& U) const {
  for (const auto& p : model_.prescribed) {
    const Vec3 d = p.displacement * model_.function_value(p.function, t);
    for (int n : p.nodes) U.col(n) = model_.start_displacement(n) + d;
  }
}

NodePositions MechanicalSystem::displacements(double t, const VecX& u) const {
  NodePositions U = model_.U0.size() ? model_.U0 : NodePositions::Zero(3, model_.num_nodes());
  apply_prescribed(t, U);
  dofs_.scatter(u, U);
  return U;
}

NodePositions MechanicalSystem::velocities(const VecX& v) const {
  NodePositions V = NodePositions::Zero(3, model_.num_nodes());
  dofs_.scatter(v, V);
  return V;
}

void MechanicalSystem::set_positions(double t, const VecX& u) {
  explicit_at_ = {};
  for (const auto& b : model_.blocks) b->set_time(t);  // sections that change in time
  if (dofs_.has_frames()) {
    if (model_.U0.size())
      U_ = model_.U0;
    else
      U_.setZero(3, model_.num_nodes());
    apply_prescribed(t, U_);
    dofs_.scatter(u, U_);
    x_ = model_.X + U_;
    return;
  }
  // x = X + U in one pass shared between the threads, U from u where a component has an
  // equation, else the start displacement (U0, or none), then the prescribed motions at
  // their eliminated components: the same bits as building U first.
  const long n = 3L * model_.num_nodes();
  x_.resize(3, model_.num_nodes());
  const double* X = model_.X.data();
  const double* U0 = model_.U0.size() ? model_.U0.data() : nullptr;
  const int* eq = dofs_.equations();
  double* x = x_.data();
  parallel_ranges(n, [&](long first, long last) {
    for (long k = first; k < last; ++k) x[k] = X[k] + (eq[k] >= 0 ? u[eq[k]] : U0 ? U0[k] : 0.0);
  });
  for (const auto& p : model_.prescribed) {
    const Vec3 d = p.displacement * model_.function_value(p.function, t);
    for (int node : p.nodes) {
      const Vec3 U = model_.start_displacement(node) + d;
      for (int c = 0; c < 3; ++c)
        if (eq[3 * node + c] < 0) x_(c, node) = model_.X(c, node) + U[c];
    }
  }
}

void MechanicalSystem::start_loads(double t, const VecX& u, const VecX& v) {
  std::optional<Assembler::LocalShare> share;
  if (distributed()) share.emplace(assembler_);
  set_positions(t, u);
  if (velocity_) V_ = velocities(v);
  const LoadState s{.t = t, .x = x_, .V = V_};
  for (const auto& term : terms_) term->start(s);
}

void MechanicalSystem::accept(double t, const VecX& u, const VecX& v, bool at_last_evaluation) {
  std::optional<Assembler::LocalShare> share;
  if (distributed()) share.emplace(assembler_);
  if (at_last_evaluation && explicit_at_.u == u.data() && explicit_at_.size == u.size() &&
      (explicit_at_.t == t || model_.prescribed.empty()))
    for (const auto& b : model_.blocks) b->set_time(t);  // x_ is that of (t, u) already
  else
    set_positions(t, u);
  if (velocity_) V_ = velocities(v);
  const LoadState s{.t = t, .x = x_, .V = V_};
  for (const auto& term : terms_) term->commit(s);
  // The laws' history per integration point (plasticity), at the accepted positions.
  for (const auto& b : model_.blocks)
    if (b->history_size() > 0) b->commit_history(x_);
}

std::vector<double> MechanicalSystem::save_load_state() const {
  std::vector<double> out{static_cast<double>(terms_.size())};
  for (const auto& term : terms_) {
    const size_t at = out.size();
    out.push_back(0);
    term->save_state(out);
    out[at] = static_cast<double>(out.size() - at - 1);
  }
  // Then the laws' history of the blocks that keep one (none: nothing is added, so the state
  // of a model without such laws is as it was).
  const std::vector<double> h = save_law_history();
  out.insert(out.end(), h.begin(), h.end());
  return out;
}

void MechanicalSystem::restore_load_state(const std::vector<double>& in) {
  if (in.empty() || in[0] != static_cast<double>(terms_.size()))
    throw std::invalid_argument("the loads' saved state does not fit this model's loads");
  size_t at = 1;
  for (const auto& term : terms_) {
    if (at >= in.size()) throw std::invalid_argument("the loads' saved state is cut short");
    const auto n = static_cast<size_t>(in[at++]);
    if (term->restore_state(in, at) != at + n)
      throw std::invalid_argument("the loads' saved state does not fit this model's loads");
    at += n;
  }
  if (at < in.size()) restore_law_history(in, at);  // none saved: the blocks keep theirs
}

std::vector<double> MechanicalSystem::save_law_history() const {
  // Its count of blocks, then each one's index, length and values; empty when no law keeps one.
  // The values are every element's, in element order (a process's held ones only otherwise):
  // the one-process format, so that a checkpoint's first process writes the whole history.
  std::vector<double> out;
  std::vector<int> with;
  for (size_t b = 0; b < model_.blocks.size(); ++b)
    if (model_.blocks[b]->history_per_element() > 0) with.push_back(static_cast<int>(b));
  if (with.empty()) return out;
  out.push_back(static_cast<double>(with.size()));
  std::vector<double> held;
  for (int b : with) {
    const ElementBlock& blk = *model_.blocks[static_cast<size_t>(b)];
    out.push_back(b);
    if (!distributed()) {
      out.push_back(static_cast<double>(blk.history_size()));
      blk.save_history(out);
      continue;
    }
    // Several processes: each element is held by one; its values at its place, zeros
    // elsewhere, summed over the processes (the same on every one).
    const size_t p = blk.history_per_element(), n = static_cast<size_t>(blk.size()) * p;
    out.push_back(static_cast<double>(n));
    const size_t at = out.size();
    out.resize(at + n, 0.0);
    held.clear();
    blk.save_history(held);
    size_t k = 0;  // the held elements' histories, in ascending element order
    for (int e = 0; e < blk.size(); ++e)
      if (blk.holds(e)) {
        if (k + p > held.size())
          throw std::logic_error("a block's history does not match its held elements");
        std::copy_n(held.begin() + static_cast<std::ptrdiff_t>(k), p,
                    out.begin() + static_cast<std::ptrdiff_t>(at + static_cast<size_t>(e) * p));
        k += p;
      }
    processes::sum(out.data() + at, static_cast<long>(n));
  }
  return out;
}

void MechanicalSystem::restore_law_history(const std::vector<double>& in, size_t at) {
  if (at >= in.size()) return;
  const auto count = static_cast<size_t>(in[at++]);
  std::vector<double> held;
  for (size_t k = 0; k < count; ++k) {
    if (at + 2 > in.size()) throw std::invalid_argument("the laws' saved history is cut short");
    const auto b = static_cast<size_t>(in[at]);
    const auto n = static_cast<size_t>(in[at + 1]);
    at += 2;
    if (b >= model_.blocks.size())
      throw std::invalid_argument("the laws' saved history does not fit this model's blocks");
    ElementBlock& blk = *model_.blocks[b];
    if (!distributed()) {
      if (blk.history_size() != n)
        throw std::invalid_argument("the laws' saved history does not fit this model's blocks");
      at = blk.restore_history(in, at);
      continue;
    }
    // Several processes: every element's history saved; this process takes its held ones'.
    const size_t p = blk.history_per_element();
    if (p == 0 || n != static_cast<size_t>(blk.size()) * p || at + n > in.size())
      throw std::invalid_argument("the laws' saved history does not fit this model's blocks");
    held.clear();
    for (int e = 0; e < blk.size(); ++e)
      if (blk.holds(e)) {
        const auto from = in.begin() + static_cast<std::ptrdiff_t>(at + static_cast<size_t>(e) * p);
        held.insert(held.end(), from, from + static_cast<std::ptrdiff_t>(p));
      }
    if (held.size() != blk.history_size())
      throw std::invalid_argument("the laws' saved history does not fit this model's blocks");
    blk.restore_history(held, 0);
    at += n;
  }
}

std::optional<double> MechanicalSystem::load_quantity(std::string_view name, int i) const {
  for (const auto& term : terms_)
    if (auto q = term->quantity(name); q && i-- == 0) return q;
  return {};
}

std::optional<double> MechanicalSystem::load_quantity_at(std::string_view name, int i, double t,
                                                         const NodePositions& x) const {
  for (const auto& term : terms_)
    if (term->quantity(name) && i-- == 0) return term->quantity_at(name, t, x);
  return {};
}

std::vector<double> MechanicalSystem::load_cell_field(std::string_view name, double t,
                                                      const NodePositions& x) const {
  std::vector<double> per_cell;
  std::vector<int> first(model_.blocks.size(), 0);
  for (size_t b = 1; b < model_.blocks.size(); ++b)
    first[b] = first[b - 1] + model_.blocks[b - 1]->size();
  for (const auto& term : terms_) {
    if (!term->quantity(name)) continue;
    if (per_cell.empty()) per_cell.assign(static_cast<size_t>(model_.num_elements()), 0.0);
    term->cell_field(name, t, x, first, per_cell);
  }
  return per_cell;
}

std::vector<double> MechanicalSystem::load_node_field(std::string_view name, double t,
                                                      const NodePositions& x) const {
  std::vector<double> per_node(static_cast<size_t>(model_.num_nodes()),
                               std::numeric_limits<double>::quiet_NaN());
  bool any = false;
  for (const auto& term : terms_) any = term->node_field(name, t, x, per_node) || any;
  if (!any) per_node.clear();
  return per_node;
}

double MechanicalSystem::load_stiffness_over_mass() const {
  double most = 0;
  const std::span<const double> m(lumped_nodes_.data(), static_cast<size_t>(lumped_nodes_.size()));
  for (const auto& term : terms_) most = std::max(most, term->max_stiffness_over_mass(m));
  return max_over_processes(most);
}

void MechanicalSystem::assemble_external(double t, const VecX& v, SparseMatrix* Kload, bool fused,
                                         bool at_supports) {
  // The nodal passes (zero, + Fp) shared between the threads: an explicit step's vector work.
  Fext_.resize(3, model_.num_nodes());
  const long entries = Fext_.size();
  parallel_ranges(entries, [&](long first, long last) {
    std::fill(Fext_.data() + first, Fext_.data() + last, 0.0);
  });
  auto add_pressures = [&] {
    if (Fp_.size() != entries) return;  // no block: no block pressure
    parallel_ranges(entries, [&](long first, long last) {
      for (long k = first; k < last; ++k) Fext_.data()[k] += Fp_.data()[k];
    });
  };
  if (Kload) {
    low_rank_.U.resize(size(), low_rank_columns_);
    low_rank_.W.resize(size(), low_rank_columns_);
  }
  if (velocity_) V_ = velocities(v);
  const LoadState s{.t = t, .x = x_, .V = V_, .fused = fused, .at_supports = at_supports};
  LoadOutput out{.F = Fext_, .K = Kload, .low_rank = &low_rank_, .column = 0};
  // The loads in their order; the follower pressures of the blocks' internal pass (Fp_)
  // join the sum after the other surface loads.
  bool surface_done = !fused;
  for (size_t i = 0; i < terms_.size(); ++i) {
    if (!surface_done && model_.loads[i].order() > LoadOrder::kSurface) {
      add_pressures();
      surface_done = true;
    }
    terms_[i]->add(s, out);
    out.column += terms_[i]->low_rank_columns();
  }
  if (!surface_done) add_pressures();
}

void MechanicalSystem::update_couplings() {
  bool changed = false;
  for (const auto& term : terms_) changed = term->update_couplings(x_) || changed;
  if (!changed) return;
  couplings_.clear();
  for (const auto& term : terms_) term->couplings(couplings_);
  const long was = assembler_.pattern_revision();
  assembler_.set_couplings(couplings_);
  if (assembler_.pattern_revision() == was) return;
  // The matrices on the old pattern: made again when next needed.
  K_ = SparseMatrix();
  M_ = SparseMatrix();
  M_entries_ = SparseMatrix();
  have_mass_ = false;
}

void MechanicalSystem::evaluate(double t, const VecX& u, const VecX& v, const VecX& a, double cu,
                                double cv, double ca, VecX& r, SparseMatrix* J) {
  // Several processes: every force is this process's share (its elements, the nodal terms of
  // its kept nodes), summed into the owners of its equations (complete) once gathered.
  std::optional<Assembler::LocalShare> share;
  if (distributed()) share.emplace(assembler_);
  set_positions(t, u);
  const double beta = model_.rayleigh_stiffness, alpha = model_.rayleigh_mass;
  // No Jacobian and no shift: the forces of an explicit step.
  const bool explicit_step = !J && cu == 0 && cv == 0 && ca == 0;
  // J = (cu + β cv) K + (α cv + ca) M − cu Kp + cv ∂(drag)/∂v, built in place as
  // cu (ck/cu K − Kp) + cm M: the load stiffness is added straight into J with unit weight.
  const double ck = cu + beta * cv, cm = alpha * cv + ca;
  const long pattern = assembler_.pattern_revision();
  if (J && cu != 0) update_couplings();
  if (J && (J->rows() != size() || J->nonZeros() != assembler_.nonzeros() ||
            pattern != assembler_.pattern_revision()))
    assembler_.make_matrix(*J);
  if (beta != 0) {  // K v enters the residual: K is kept apart
    if (K_.nonZeros() != assembler_.nonzeros() || pattern != assembler_.pattern_revision())
      assembler_.make_matrix(K_);
    assembler_.internal(x_, Fint_, &K_);
    if (J) combine_values(*J, 0.0, &K_, cu != 0 ? ck / cu : ck);
    assemble_external(t, v, J && cu != 0 ? J : nullptr);
  } else {
    // Pressures on whole blocks go through the blocks' internal pass: one scatter of
    // K − Kp instead of two (the matrix is the largest thing a Newton iteration walks).
    block_pressure_.assign(model_.blocks.size(), 0.0);
    int block = 0;
    double p = 0;
    for (const auto& term : terms_)
      if (term->whole_block_pressure(t, block, p)) block_pressure_[block] += p;
    // An explicit step's forces take the blocks' explicit path (equal to round-off;
    // implicit results untouched).
    if (explicit_step) {
      explicit_at_ = {.u = u.data(), .size = u.size(), .t = t};
      assembler_.explicit_forces(x_, Fint_, block_pressure_, Fp_);
    } else {
      assembler_.internal(x_, Fint_, J && cu != 0 ? J : nullptr, block_pressure_, Fp_);
    }
    if (J && cu == 0) combine_values(*J, 0.0, nullptr, 0.0);
    assemble_external(t, v, J && cu != 0 ? J : nullptr, true);
  }
  if (J && cu != 0 && cu != 1) low_rank_.U *= cu;
  if (J && cu == 0) low_rank_ = {};

  dofs_.gather_difference(Fint_, Fext_, r);
  // An explicit step's forces on several processes: the shares of M a and M v join the
  // force's share before the one exchange that completes them all (each process decides on
  // its own vectors: a process whose a is zero adds a zero share), and no force scale (no
  // Newton reads it). One exchange with the neighbours per step instead of five collective
  // calls; the sums differ from one process's in their order only (round-off).
  const bool shares = distributed() && explicit_step && beta == 0;
  if (!shares) complete(r);
  // M a and, with mass damping, M v: one walk of M for both (each product summed in the
  // same order as Eigen's, so bit for bit the same as two products).
  // Decided on the reduced norms: complete() below is a collective call. An explicit step
  // (on one process, or sharing) decides on its own vectors, and needs no force scale (no
  // Newton reads it): M a only when a is not zero (a central-difference step's a is).
  const bool local = explicit_step && (shares || !distributed());
  auto nonzero = [&](const VecX& x) { return local ? any_nonzero(x) : squared_norm(x) != 0; };
  const bool inertia = nonzero(a), damping = alpha != 0 && nonzero(v);
  if (!explicit_step || inertia) mv_.setZero(r.size());
  if (damping) mvv_.setZero(r.size());
  if (inertia || damping) {
    const SparseMatrix& M = mass_entries();
    const int* outer = M.outerIndexPtr();
    const int* inner = M.innerIndexPtr();
    const double* mv = M.valuePtr();
    for (int j = 0; j < M.outerSize(); ++j) {
      const double aj = inertia ? a[j] : 0.0, vj = damping ? v[j] : 0.0;
      if (!damping) {
        for (int k = outer[j]; k < outer[j + 1]; ++k) mv_[inner[k]] += mv[k] * aj;
      } else if (!inertia) {  // an explicit step's M v alone (mv_ is not sized then)
        for (int k = outer[j]; k < outer[j + 1]; ++k) mvv_[inner[k]] += mv[k] * vj;
      } else {
        for (int k = outer[j]; k < outer[j + 1]; ++k) {
          mv_[inner[k]] += mv[k] * aj;
          mvv_[inner[k]] += mv[k] * vj;
        }
      }
    }
    if (inertia) {
      if (!shares) complete(mv_);
      r += mv_;
    }
    if (damping) {
      if (!shares) complete(mvv_);
      r += alpha * mvv_;
    }
  }
  if (shares) {
    complete(r);
    force_scale_ = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (beta != 0) {
    VecX Kv = K_ * v;
    complete(Kv);
    r += beta * Kv;
  }
  if (local) {
    force_scale_ = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  force_scale_ = distributed() ? distributed_force_scale()
                               : std::max({Fint_.norm(), Fext_.norm(), mv_.norm()});

  if (!J) return;
  if (cu != 0) {
    // J holds K − Kp here (unscaled): the stiffness that turns a ulp of x into force. One
    // pass over the entries gives the round-off level ε ‖|K − Kp|ᵀ |x|‖ (column by column:
    // no two threads write one entry; for a symmetric J it is ε ‖|J| |x|‖) and makes J =
    // cu (K − Kp) + cm M (the matrix is the largest thing an iteration walks).
    dofs_.gather(x_, x_eq_);
    noise_eq_.resize(size());
    const int* outer = J->outerIndexPtr();
    const int* inner = J->innerIndexPtr();
    double* jv = J->valuePtr();
    const double* mv = cm != 0 ? mass_matrix().valuePtr() : nullptr;
    parallel_for(
        static_cast<int>(J->outerSize()), J->nonZeros() > kParallelMatrixEntries, [&](int j) {
          double sum = 0;
          if (mv) {
            for (int k = outer[j]; k < outer[j + 1]; ++k) {
              sum += std::abs(jv[k] * x_eq_[inner[k]]);
              jv[k] = cu * jv[k] + cm * mv[k];
            }
          } else if (cu != 1) {
            for (int k = outer[j]; k < outer[j + 1]; ++k) {
              sum += std::abs(jv[k] * x_eq_[inner[k]]);
              jv[k] *= cu;
            }
          } else {  // statics: J is K − Kp as assembled, and a pass that writes nothing is faster
            for (int k = outer[j]; k < outer[j + 1]; ++k) sum += std::abs(jv[k] * x_eq_[inner[k]]);
          }
          noise_eq_[j] = sum;
        });
    // On several processes: the sum of the shares' |J| |x| (equal to |J| |x| except where
    // two processes add into one entry, where it bounds it from above).
    complete(noise_eq_);
    residual_noise_ = std::numeric_limits<double>::epsilon() * norm(noise_eq_);
  } else if (cm != 0) {
    combine_values(*J, 1.0, &mass_matrix(), cm);
  }
  // Velocity-dependent loads (payload drag): cv ∂(−f)/∂v.
  if (velocity_ && cv != 0)
    for (const auto& term : terms_) term->add_velocity_jacobian(V_, cv, *J);
}

const NodePositions& MechanicalSystem::external_forces(double t, const VecX& u, const VecX& v,
                                                       bool at_supports) {
  std::optional<Assembler::LocalShare> share;
  if (distributed()) share.emplace(assembler_);
  set_positions(t, u);
  assemble_external(t, v, nullptr, false, at_supports);
  return Fext_;
}

NodePositions MechanicalSystem::reactions(double t, const VecX& u, const VecX& v) {
  std::optional<Assembler::LocalShare> share;
  if (distributed()) share.emplace(assembler_);
  set_positions(t, u);
  assembler_.internal(x_, Fint_, nullptr);
  assemble_external(t, v, nullptr, false, true);
  NodePositions R = Fint_ - Fext_;
  dofs_.keep_eliminated(R);
  return R;
}

double MechanicalSystem::strain_energy(double t, const VecX& u) const {
  const NodePositions x = model_.X + displacements(t, u);
  double U = 0;
  for (const auto& b : model_.blocks) b->set_time(t);
  for (size_t b = 0; b < model_.blocks.size(); ++b)
    U += model_.blocks[b]->strain_energy(assembler_.own(static_cast<int>(b)), x);
  if (processes::count() > 1) processes::sum(&U, 1);  // each process's elements
  return U;
}

double MechanicalSystem::section_work(double t0, const NodePositions& U0, double t1,
                                      const NodePositions& U1) const {
  double W = 0;
  std::optional<NodePositions> x0, x1;  // made once, for the first block that changes in time
  for (size_t b = 0; b < model_.blocks.size(); ++b) {
    ElementBlock& blk = *model_.blocks[b];
    if (!blk.changes_in_time()) continue;
    if (!x0) x0 = model_.X + U0, x1 = model_.X + U1;
    const auto own = assembler_.own(static_cast<int>(b));
    double at[2][2];  // [time][positions]
    for (int k = 0; k < 2; ++k) {
      blk.set_time(k == 0 ? t0 : t1);
      at[k][0] = blk.strain_energy(own, *x0);
      at[k][1] = blk.strain_energy(own, *x1);
    }
    W += 0.5 * ((at[1][0] - at[0][0]) + (at[1][1] - at[0][1]));
  }
  if (x0 && processes::count() > 1) processes::sum(&W, 1);
  return W;
}

std::string MechanicalSystem::inverted_element(double t_from, const VecX& u_from, double t_to,
                                               const VecX& u_to) const {
  const NodePositions from = model_.X + displacements(t_from, u_from);
  const NodePositions to = model_.X + displacements(t_to, u_to);
  // Each process checks its own elements; the first inverted one in the model's order (over
  // the processes: the smallest cell index) is named on every process alike.
  long first = model_.num_elements(), cell = 0;
  for (size_t b = 0; b < model_.blocks.size(); ++b) {
    const int e = model_.blocks[b]->first_inverted(assembler_.own(static_cast<int>(b)), from, to);
    if (e >= 0) {
      first = cell + e;
      break;
    }
    cell += model_.blocks[b]->size();
  }
  if (processes::count() > 1) first = processes::min(first);
  cell = 0;
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi) {
    const ElementBlock& b = *model_.blocks[bi];
    const long e = first - cell;
    cell += b.size();
    if (e >= b.size()) continue;
    // Its nodes' ids from the process computing it (a piece holds its own elements' nodes).
    std::vector<long> ids;
    if (assembler_.owns(static_cast<int>(bi), static_cast<int>(e)))
      ids = node_ids_of(model_, b, static_cast<int>(e));
    if (processes::count() > 1) {
      std::vector<double> sum(static_cast<size_t>(b.nodes_per_element()), 0.0);
      for (size_t k = 0; k < ids.size(); ++k) sum[k] = static_cast<double>(ids[k]);
      processes::sum(sum.data(), static_cast<long>(sum.size()));
      ids.assign(sum.begin(), sum.end());
    }
    return fmt::format(
        "{} element {} of set '{}' (nodes {}) turns inside out between t = {:.6g} and "
        "{:.6g}",
        b.type_name(), e + 1, b.set_name(), fmt::join(ids, " "), t_from, t_to);
  }
  return {};
}

VecX MechanicalSystem::abs_diagonal(const SparseMatrix& J) const {
  // On the assembler's pattern the diagonal is read where the assembler found it
  // (J.diagonal() searches each column, a binary search per equation, once a step).
  const std::vector<int>& at = assembler_.diagonal_positions();
  VecX d;
  if (J.nonZeros() == assembler_.nonzeros() &&
      J.outerSize() == static_cast<Eigen::Index>(at.size())) {
    d.setZero(J.outerSize());
    for (Eigen::Index j = 0; j < d.size(); ++j)
      if (const int k = at[static_cast<size_t>(j)]; k >= 0) d[j] = J.valuePtr()[k];
  } else {
    d = J.diagonal();
  }
  complete(d);  // the shares' diagonals add up to J's
  return d.cwiseAbs();
}

bool MechanicalSystem::stiffen_stress_free(SparseMatrix& J) const {
  // Stress-free: no internal force at any node, supports included (where a prestress shows).
  const double stressed = Fint_.size() > 0 ? Fint_.cwiseAbs().maxCoeff() : 0.0;
  if (max_over_processes(stressed) != 0 || J.nonZeros() != assembler_.nonzeros()) return false;
  // Soft: the stiffness of some equation below kSoft of the largest. The Hencky membrane's
  // shallow stress-free dome (a tenth of the expected deflection high): 3.9e-11; the same
  // sheet under its first load step's tension: 4.8e-7; curved or triangulated structures:
  // far above.
  constexpr double kSoft = 1e-6;
  const VecX d = abs_diagonal(J);
  const double dmax = max_abs(d);
  double dmin = std::numeric_limits<double>::infinity();
  for (int e = 0; e < owned_size(); ++e) dmin = std::min(dmin, d[e]);
  dmin = -max_over_processes(-dmin);
  if (!(dmax > 0) || !(dmin < kSoft * dmax)) return false;
  // Added element by element, with no matrix of T: a stress-free start needs it once (again
  // only after a cut-back), and a matrix of it, even one freed on return, is one matrix's
  // memory more first touched (Hencky n = 130: 49 MB; each MB first touched costs about a
  // millisecond on the development machine: docs/performance.md).
  // A tension kTension times the largest stiffness: small beside the sheet's own stiffness
  // in its plane, so the correction keeps the in-plane response of the untensioned sheet;
  // its shape normal to it does not depend on the tension, its size (inversely proportional)
  // is the line search's. On a stress-free dome any value from 1e-5 to 1e-2 gave the same
  // first step, with fewer factorisations than without the borrowed tension.
  constexpr double kTension = 1e-3;
  VecX t = assembler_.tension_stiffness_diagonal();
  complete(t);  // the shares' diagonals add up to T's
  const double tmax = max_abs(t);
  if (!(tmax > 0)) return false;  // no membrane or cable
  assembler_.add_tension_stiffness(J, kTension * dmax / tmax);
  return true;
}

std::string MechanicalSystem::diagnose_singular(const SparseMatrix& J) const {
  // Equations whose diagonal is negligible carry no stiffness (nor mass) at all.
  const VecX d = abs_diagonal(J);
  const double dmax = max_abs(d);
  // The first 8 in the global numbering (each process's first 8 of its owned equations,
  // gathered to the first process), and the count over all of them.
  std::vector<double> first;  // (global equation, node id, component) each
  int count = 0;
  for (int n = 0; n < model_.num_nodes(); ++n)
    for (int c = 0; c < 3; ++c) {
      const int e = dofs_.equation(n, c);
      if (e >= 0 && e < owned_size() && !(d[e] > 1e-13 * dmax) && ++count <= 8)
        first.insert(first.end(), {static_cast<double>(dofs_.global_equation(n, c)),
                                   static_cast<double>(model_.node_ids[static_cast<size_t>(n)]),
                                   static_cast<double>(c)});
    }
  count = static_cast<int>(sum_over_processes(count));
  if (distributed()) first = processes::gather(first);  // in rank order: ascending
  if (count == 0) return {};
  std::vector<std::string> bad;
  for (size_t k = 0; k + 2 < first.size() && bad.size() < 8; k += 3)
    bad.push_back(fmt::format("node {} {}", static_cast<long>(first[k + 1]),
                              "xyz"[static_cast<int>(first[k + 2])]));
  return fmt::format(
      "{} unconstrained DOF(s) with no stiffness and no mass ({}{}). A flat, unstressed membrane "
      "has no stiffness normal to its plane: a static analysis starts it with its line search "
      "on (newton.line_search, the default); else give it mass and run a dynamic analysis, add "
      "prestress, or constrain those DOFs",
      count, fmt::join(bad, ", "), count > 8 ? ", ..." : "");
}

}  // namespace velum
