// Projective dynamics' constant matrix M + h D + h^2 K (projective_dynamics.cpp) over the
// active particles of a system: the unknowns numbered in a fill-reducing (AMD) order for a
// factorisation, or in the particles' order for the multigrid (which needs no fill-reducing
// order and whose setup stays linear without it), and M, D and K as upper triangles in one
// sparsity pattern, so that the matrix of any h is formed value by value. Shared by the plugin
// and bench/pd_factorization.cpp.
#pragma once

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cstdint>
#include <utility>
#include <vector>

namespace clothlab::builtin {

class ProjectiveDynamicsMatrix {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  enum class Order { kFillReducing, kParticles };

  template <class Real>
  void build(const sdk::System<Real>& system, const sdk::Topology& topology,
             Order order = Order::kFillReducing) {
    number_unknowns(system, topology, order);
    assemble(system, topology);
  }

  // unknown_of()[particle] = its row in the global system, -1 when pinned.
  const std::vector<int32_t>& unknown_of() const { return unknown_of_; }
  // The inverse: node_of()[row] = the particle of that row.
  std::vector<uint32_t> node_of() const {
    std::vector<uint32_t> nodes(static_cast<size_t>(unknowns()));
    for (uint32_t i = 0; i < unknown_of_.size(); ++i)
      if (unknown_of_[i] >= 0) nodes[static_cast<size_t>(unknown_of_[i])] = i;
    return nodes;
  }
  const std::vector<double>& mass() const { return mass_; }  // per unknown
  Eigen::Index unknowns() const { return stiffness_.rows(); }
  const Matrix& damping_upper() const { return damping_upper_; }

  // M (a matrix in the shared pattern), for the caller to overwrite with combine().
  const Matrix& pattern() const { return mass_matrix_; }
  // The values of M + h D + h^2 K into `matrix`, a copy of pattern().
  void combine(double h, Matrix& matrix) const {
    const Eigen::Index nonzeros = matrix.nonZeros();
    double* values = matrix.valuePtr();
    for (Eigen::Index k = 0; k < nonzeros; ++k)
      values[k] = mass_matrix_.valuePtr()[k] + h * damping_upper_.valuePtr()[k] +
                  h * h * stiffness_.valuePtr()[k];
  }

 private:
  template <class Real>
  void number_unknowns(const sdk::System<Real>& system, const sdk::Topology& topology,
                       Order order) {
    const uint32_t n = system.particle_count();
    std::vector<int32_t> natural(n, -1);
    int32_t count = 0;
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) natural[i] = count++;
    if (order == Order::kParticles) {
      unknown_of_ = std::move(natural);
      return;
    }
    std::vector<Eigen::Triplet<double, int>> entries;
    for (int32_t u = 0; u < count; ++u) entries.emplace_back(u, u, 1.0);
    for (uint32_t s = 0; s < topology.spring_count(); ++s) {
      const int32_t a = natural[topology.first()[s]], b = natural[topology.second()[s]];
      if (a < 0 || b < 0) continue;
      entries.emplace_back(a, b, 1.0);
      entries.emplace_back(b, a, 1.0);
    }
    Matrix graph(count, count);
    graph.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> elimination_order;
    Eigen::AMDOrdering<int>()(graph, elimination_order);
    // AMD returns the elimination order; row u of the reordered system is the unknown
    // eliminated u-th (as SimplicialLDLT applies it: P = order^-1).
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> new_row =
        elimination_order.inverse();
    unknown_of_.assign(n, -1);
    for (uint32_t i = 0; i < n; ++i)
      if (natural[i] >= 0) unknown_of_[i] = new_row.indices()[natural[i]];
  }

  template <class Real>
  void assemble(const sdk::System<Real>& system, const sdk::Topology& topology) {
    const auto count = static_cast<Eigen::Index>(
        std::count_if(unknown_of_.begin(), unknown_of_.end(), [](int32_t u) { return u >= 0; }));
    mass_.assign(static_cast<size_t>(count), 0.0);
    for (uint32_t i = 0; i < unknown_of_.size(); ++i)
      if (unknown_of_[i] >= 0) mass_[unknown_of_[i]] = 1.0 / system.inverse_mass()[i];

    struct Entry {
      int32_t row, col;
      double mass, kd, ks;
    };
    std::vector<Entry> entries;
    for (Eigen::Index u = 0; u < count; ++u)
      entries.push_back({static_cast<int32_t>(u), static_cast<int32_t>(u), mass_[u], 0, 0});
    for (uint32_t s = 0; s < topology.spring_count(); ++s) {
      const int32_t a = unknown_of_[topology.first()[s]], b = unknown_of_[topology.second()[s]];
      const double ks = topology.ks()[s], kd = topology.kd()[s];
      if (a >= 0) entries.push_back({a, a, 0, kd, ks});
      if (b >= 0) entries.push_back({b, b, 0, kd, ks});
      if (a >= 0 && b >= 0) entries.push_back({std::min(a, b), std::max(a, b), 0, -kd, -ks});
    }
    const auto upper = [&](double Entry::*field) {
      std::vector<Eigen::Triplet<double, int>> triplets;
      triplets.reserve(entries.size());
      for (const Entry& e : entries) triplets.emplace_back(e.row, e.col, e.*field);
      Matrix matrix(count, count);
      matrix.setFromTriplets(triplets.begin(), triplets.end());  // keeps explicit zeros
      return matrix;
    };
    mass_matrix_ = upper(&Entry::mass);
    damping_upper_ = upper(&Entry::kd);
    stiffness_ = upper(&Entry::ks);
  }

  std::vector<int32_t> unknown_of_;
  std::vector<double> mass_;
  Matrix mass_matrix_, damping_upper_, stiffness_;
};

}  // namespace clothlab::builtin
