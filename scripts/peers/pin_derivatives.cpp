// Native (no Python) timing of Pinocchio's computeABADerivatives (the
// analytic derivatives of forward dynamics: ddq_dq, ddq_dv and Minv) on the
// peers' benchmark chain (shared/bench/peers/chain_common.py) at its test
// state, for comparison with our `aba_derivatives/N` criterion group.
// Header-only use of the Pinocchio 4.1.0 headers in the `pin` wheel
// (cmeel.prefix) and Debian's Eigen 3.4, with the flags of the peers'
// native/build_native.sh. Build and run: see build_pin_derivatives.sh.
// Output: CSV `pinocchio-c++,aba_derivatives,N,median_ns` on stdout.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

using namespace pinocchio;

// The chain exactly as the peers' pin_bench.cpp builds it.
static Model build_chain(int n) {
  Model model;
  model.gravity.linear(Eigen::Vector3d(0, 0, -9.81));
  Inertia I(1.0, Eigen::Vector3d(0.5, 0, 0),
            Eigen::Vector3d(1e-3, 1.0 / 12, 1.0 / 12).asDiagonal().toDenseMatrix());
  JointIndex parent = 0;
  for (int k = 0; k < n; ++k) {
    SE3 placement(Eigen::Matrix3d::Identity(), Eigen::Vector3d(k == 0 ? 0.0 : 1.0, 0, 0));
    JointIndex jid;
    if (k % 2 == 0)
      jid = model.addJoint(parent, JointModelRZ(), placement, "j" + std::to_string(k));
    else
      jid = model.addJoint(parent, JointModelRY(), placement, "j" + std::to_string(k));
    model.appendBodyToJoint(jid, I, SE3::Identity());
    parent = jid;
  }
  return model;
}

static volatile double sink;

// The same measurement as pin_bench.cpp: batches of at least 20 ms, median of 21.
template <class F> static double median_ns(F &&f) {
  using clk = std::chrono::steady_clock;
  for (int i = 0; i < 1000; ++i) f();
  long m = 1;
  for (;;) {
    auto t0 = clk::now();
    for (long i = 0; i < m; ++i) f();
    double dt = std::chrono::duration<double>(clk::now() - t0).count();
    if (dt > 0.02) break;
    m *= 2;
  }
  std::vector<double> s;
  for (int r = 0; r < 21; ++r) {
    auto t0 = clk::now();
    for (long i = 0; i < m; ++i) f();
    s.push_back(std::chrono::duration<double, std::nano>(clk::now() - t0).count() / m);
  }
  std::sort(s.begin(), s.end());
  return s[s.size() / 2];
}

int main() {
  int Ns[] = {7, 30, 100};
  std::printf("tool,what,N,median_ns\n");
  for (int n : Ns) {
    Model model = build_chain(n);
    Data data(model);
    Eigen::VectorXd q(n), v(n), tau = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; ++k) { q[k] = 0.1 * (k + 1); v[k] = 0.05 * (k + 1); }
    computeABADerivatives(model, data, q, v, tau);
    // A value to compare with the golden file (stderr only).
    std::fprintf(stderr, "N=%d ddq_dq(0,0)=%.15g ddq_dv(n-1,0)=%.15g Minv(0,n-1)=%.15g\n", n,
                 data.ddq_dq(0, 0), data.ddq_dv(n - 1, 0), data.Minv(0, n - 1));
    double t = median_ns([&] {
      computeABADerivatives(model, data, q, v, tau);
      sink = data.ddq_dq(0, 0);
    });
    std::printf("pinocchio-c++,aba_derivatives,%d,%.1f\n", n, t);
    std::fflush(stdout);
  }
}
