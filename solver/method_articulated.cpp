// The articulated-body method (not in the paper; docs/theory.md §14): u' in
// O(n) from the kinematics alone, without forming A or B. Featherstone's
// articulated-body algorithm (Rigid Body Dynamics Algorithms, 2008, ch. 7)
// written in the project's frame: every spatial quantity of body k has world
// axes and is taken about its joint point o_k, so a parent-child transform is
// the shift by the lever d_k (eq. (AB1)) and no rotation ever multiplies a
// 6x6 block. Symbols as theory.md §14 names them (Featherstone's S, I^A, p^A,
// U, D, u are Pi, Y, beta, Xi, Delta, eps there).
#include <iterator>
#include <stdexcept>
#include <type_traits>

#include "solver/applied_forces.hpp"
#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// A symmetric 6x6 spatial inertia about a joint point, world axes (eq. (AB2)):
// [[ww, wv], [wv^T, vv]] acting on (angular, linear) accelerations.
struct Inertia6 {
  Mat3 ww, wv, vv;  // (3x3) each; ww and vv symmetric
};

// [l]x X: l x each column of X.
inline Mat3 crossCols(const Vec3& l, const Mat3& X) {
  Mat3 out;
  for (int c = 0; c < 3; ++c) out.col(c) = l.cross(X.col(c));
  return out;
}

// Phi(l) Y Phi(l)^T added to `to`: a child's inertia shifted to its parent's
// joint point, l = d_c (eq. (AB4)); with wv' = wv + [l]x vv:
// ww += ww_c + [l]x wv^T - wv' [l]x, wv += wv', vv += vv_c.
inline void addShifted(const Vec3& l, const Inertia6& Y, Inertia6& to) {
  const Mat3 wv = Y.wv + crossCols(l, Y.vv);
  to.ww += Y.ww + crossCols(l, Y.wv.transpose()) + crossCols(l, wv.transpose()).transpose();
  to.wv += wv;
  to.vv += Y.vv;
}

class Articulated final : public MethodImpl {
 public:
  Articulated(const Model& m, const MethodOptions& opt)
      : m_(m), opt_(opt), Y_(m.n()), beta_w_(m.n()), beta_v_(m.n()), zeta_w_(m.n()), zeta_v_(m.n()),
        alpha_w_(m.n()), alpha_v_(m.n()), gain_w_(3, m.nu), gain_v_(3, m.nu), Dinv_eps_(m.nu), Q_(m.nu) {}

  bool needsEquations() const override { return false; }
  bool needsA() const override { return false; }

  Status rates(double t, const double* q, const double* u, const Workspace& ws, const double*, double* udot, double*,
               EvalInfo&) override {
    Q_.setZero();
    if (m_.hasAppliedForces()) addAppliedForces(m_, ws, q, u, Q_);
    bodiesAndBiases(u, ws);
    for (int k = m_.n() - 1; k >= 0; --k) {
      const Status s = dispatch(k, [&](auto nu, auto nt) { return release<nu(), nt()>(k, t, ws); });
      if (!s) return s;
    }
    for (int k = 0; k < m_.n(); ++k)
      dispatch(k, [&](auto nu, auto nt) {
        accelerate<nu(), nt()>(k, ws, udot);
        return Status{};
      });
    return {};
  }

 private:
  template <int V>
  using Int = std::integral_constant<int, V>;

  // One call of f<NU, NT> for body k's joint: fixed-size blocks for the
  // (nu, nt) of each joint row (solver/model.hpp), found in table order.
  template <size_t I = 0, class F>
  Status dispatch(int k, F&& f) const {
    if constexpr (I == std::size(kJointTypes)) {
      throw std::logic_error("articulated: no joint row of " + std::to_string(m_.body_nu[k]) + " speeds");
    } else {
      constexpr int nu = kJointTypes[I].nu, nt = kJointTypes[I].nt;
      if (m_.body_nu[k] == nu && m_.body_nt[k] == nt) return f(Int<nu>{}, Int<nt>{});
      return dispatch<I + 1>(k, std::forward<F>(f));
    }
  }

  // Outward: each body's own inertia and bias force about its joint point
  // (eq. (AB2)), where the inward pass starts, and the velocity-product
  // acceleration zeta_k of joint k (eq. (AB3)).
  void bodiesAndBiases(const double* u, const Workspace& ws) {
    for (int k = 0; k < m_.n(); ++k) {
      const Body& body = m_.bodies[k];
      const int p = body.parent, nt = body.nt();
      zeta_w_[k].setZero();
      for (int j = body.iu + nt; j < body.iu + body.nu(); ++j) zeta_w_[k] += ws.Pdot.col(j) * u[j];
      if (p < 0) zeta_v_[k].setZero();
      else {
        const Vec3& w_p = ws.omega[p];
        zeta_v_[k] = w_p.cross(w_p.cross(ws.d[k]));
        if (nt > 0) zeta_v_[k] += 2.0 * w_p.cross(ws.v_rel[k]);
      }
      const double mk = body.mass;
      const Vec3& b = ws.b[k];
      const Vec3& w = ws.omega[k];
      const Vec3 mb = mk * b, wwb = w.cross(w.cross(b));
      Inertia6& Y = Y_[k];
      Y.ww = ws.J_w[k];  // J + m ((b.b) E - b b^T)
      Y.ww.noalias() -= mb * b.transpose();
      Y.ww.diagonal().array() += mb.dot(b);
      Y.wv << 0, -mb.z(), mb.y(), mb.z(), 0, -mb.x(), -mb.y(), mb.x(), 0;  // m [b]x
      Y.vv = Mat3::Zero();
      Y.vv.diagonal().setConstant(mk);
      beta_w_[k] = w.cross(ws.J_w[k] * w) + mb.cross(wwb);
      beta_v_[k] = mk * wwb;
    }
  }

  // Inward, body k (eqs. (AB5)-(AB6)): Xi = Y Pi, Delta = Pi^T Xi, the
  // joint's force balance eps = Q - Pi^T (beta + Y zeta), then the articulated
  // inertia and bias force its parent sees, Y - Xi Delta^-1 Xi^T and
  // beta + Y zeta + Xi Delta^-1 eps, shifted to the parent's joint point.
  // Keeps the gain Xi Delta^-1 and Delta^-1 eps for the outward pass.
  template <int NU, int NT>
  Status release(int k, double t, const Workspace& ws) {
    constexpr int NR = NU - NT;
    using Cols = Eigen::Matrix<double, 3, NU>;
    using Square = Eigen::Matrix<double, NU, NU>;
    const int iu = m_.body_iu[k];
    const Cols Pi = ws.P.middleCols<NU>(iu);  // the joint's world axes: slides t (first NT), rotations p
    const Inertia6& Y = Y_[k];
    Cols Xi_w, Xi_v;  // Xi = Y Pi: angular and linear rows
    if constexpr (NT > 0) {
      Xi_w.template leftCols<NT>() = Y.wv * Pi.template leftCols<NT>();
      Xi_v.template leftCols<NT>() = Y.vv * Pi.template leftCols<NT>();
    }
    if constexpr (NR > 0) {
      Xi_w.template rightCols<NR>() = Y.ww * Pi.template rightCols<NR>();
      Xi_v.template rightCols<NR>() = Y.wv.transpose() * Pi.template rightCols<NR>();
    }
    const Vec3 f_w = beta_w_[k] + Y.ww * zeta_w_[k] + Y.wv * zeta_v_[k];  // beta + Y zeta
    const Vec3 f_v = beta_v_[k] + Y.wv.transpose() * zeta_w_[k] + Y.vv * zeta_v_[k];
    Square Delta;
    Eigen::Matrix<double, NU, 1> eps = Q_.segment<NU>(iu);
    for (int j = 0; j < NU; ++j) {  // row j of Pi^T: (0, t_j) for a slide, (p_j, 0) for a rotation
      const bool slide = j < NT;
      Delta.row(j) = Vec3(Pi.col(j)).transpose() * (slide ? Xi_v : Xi_w);
      eps[j] -= Pi.col(j).dot(slide ? f_v : f_w);
    }
    Square Dinv;
    if (const Status s = invertDelta<NU>(k, t, Delta, Dinv); !s) return s;
    const Cols gain_w = Xi_w * Dinv, gain_v = Xi_v * Dinv;
    gain_w_.middleCols<NU>(iu) = gain_w;
    gain_v_.middleCols<NU>(iu) = gain_v;
    Dinv_eps_.segment<NU>(iu) = Dinv * eps;
    const int p = m_.body_parent[k];
    if (p < 0) return {};
    const Inertia6 YA{Y.ww - gain_w * Xi_w.transpose(), Y.wv - gain_w * Xi_v.transpose(), Y.vv - gain_v * Xi_v.transpose()};
    addShifted(ws.d[k], YA, Y_[p]);
    const Vec3 bA_w = f_w + gain_w * eps, bA_v = f_v + gain_v * eps;  // beta^A
    beta_w_[p] += bA_w + ws.d[k].cross(bA_v);
    beta_v_[p] += bA_v;
    return {};
  }

  // Delta^-1, checked by a Cholesky factorization: Delta is joint k's
  // articulated inertia along its own speeds. The failures mirror classical's
  // on A: not positive definite, or squared pivots spread beyond
  // max_pivot_ratio (a gimbal at its lock).
  template <int NU>
  Status invertDelta(int k, double t, const Eigen::Matrix<double, NU, NU>& Delta, Eigen::Matrix<double, NU, NU>& Dinv) const {
    const Eigen::LLT<Eigen::Matrix<double, NU, NU>> llt(Delta);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 0))
      return Status::failure(t, Failure::NotPositiveDefinite, deltaName(k) + " not positive definite (Cholesky failed)");
    if constexpr (NU > 1) {
      const auto pivots = llt.matrixLLT().diagonal().cwiseAbs2();
      if (pivots.maxCoeff() > opt_.max_pivot_ratio * pivots.minCoeff())
        return Status::failure(t, Failure::Singular, deltaName(k) + " numerically singular: cond(Delta) >= " +
                                                         gnum(pivots.maxCoeff() / pivots.minCoeff()) + " > 1/eps");
    }
    if constexpr (NU <= 4) {
      Dinv = Delta.inverse();  // Eigen's closed form (cofactors) for small fixed sizes
    } else {  // a free joint's 6 x 6: column by column (a matrix right-hand side takes Eigen's blocked, dynamic-size path)
      Dinv.setIdentity();
      for (int j = 0; j < NU; ++j) {
        auto col = Dinv.col(j);
        llt.solveInPlace(col);
      }
    }
    return {};
  }

  // How a failure names Delta (built only on failure: evaluations allocate nothing).
  std::string deltaName(int k) const {
    return "articulated inertia Delta of body '" + m_.bodies[k].name + "' (along its joint's speeds)";
  }

  // Outward, body k (eq. (AB7)): the parent's acceleration carried to joint
  // point k, u'_k = Delta^-1 eps - gain^T alpha', then body k's acceleration.
  // The ground's is (0, -g): gravity enters as a lift of the base.
  template <int NU, int NT>
  void accelerate(int k, const Workspace& ws, double* udot) {
    const int p = m_.body_parent[k], iu = m_.body_iu[k];
    const Vec3 a_w = p < 0 ? Vec3::Zero() : alpha_w_[p];
    const Vec3 a_v = p < 0 ? Vec3(-m_.gravity) : Vec3(alpha_v_[p] + alpha_w_[p].cross(ws.d[k]));
    Eigen::Map<Eigen::Matrix<double, NU, 1>> ud(udot + iu);
    ud = Dinv_eps_.segment<NU>(iu) - gain_w_.middleCols<NU>(iu).transpose() * a_w -
         gain_v_.middleCols<NU>(iu).transpose() * a_v;
    alpha_w_[k] = a_w + zeta_w_[k];
    alpha_v_[k] = a_v + zeta_v_[k];
    for (int j = 0; j < NU; ++j) (j < NT ? alpha_v_[k] : alpha_w_[k]) += ws.P.col(iu + j) * ud[j];
  }

  const Model& m_;
  MethodOptions opt_;
  std::vector<Inertia6> Y_;                   // (n) Y_k: articulated inertia about joint point k
  std::vector<Vec3> beta_w_, beta_v_;         // (n) beta_k: articulated bias force, moment about o_k and force
  std::vector<Vec3> zeta_w_, zeta_v_;         // (n) zeta_k: joint k's velocity-product accelerations
  std::vector<Vec3> alpha_w_, alpha_v_;       // (n) alpha_k: body k's angular acceleration, joint point k's (gravity lifted)
  Eigen::Matrix3Xd gain_w_, gain_v_;          // (3 x N) the gain Xi Delta^-1, by speed
  Eigen::VectorXd Dinv_eps_;                  // (N) Delta^-1 eps
  Eigen::VectorXd Q_;                         // (N) joint spring-damper forces
};

}  // namespace

std::unique_ptr<MethodImpl> makeArticulated(const Model& m, const MethodInfo&, const MethodOptions& opt) {
  return std::make_unique<Articulated>(m, opt);
}

}  // namespace em
