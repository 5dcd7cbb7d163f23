#pragma once
// The dense oracles of the formation, for tests only (docs/theory.md §4, §6).
#include "solver/formation.hpp"

namespace em::test {

/// K and K_T = T K T^T formed densely, and the axes they project on.
struct DenseK {
  Eigen::MatrixXd K, KT;  // (3n x 3n)
  Eigen::Matrix3Xd P;     // (3 x nu)
};
/// K by its barycentric blocks K_jk = kernel(d, s_k), and K_T (needs formSubtrees).
DenseK formDenseK(const Model& m, const Workspace& ws);
/// K by the naive triple sum over i, j, k.  // (3n x 3n)
Eigen::MatrixXd naiveK(const Model& m, const Workspace& ws);
/// A = P^T K_T P block by block, the dense form of eq. (2).  // (nu x nu)
Eigen::MatrixXd denseA(const Model& m, const DenseK& dk);
/// A' = P'^T K_T P + P^T K_T' P + P^T K_T P' from the dense K'.  // (nu x nu)
Eigen::MatrixXd denseAdot(const Model& m, const Workspace& ws, const DenseK& dk);

}  // namespace em::test
