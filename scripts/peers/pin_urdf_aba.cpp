// Native (no Python) timing of Pinocchio's forward dynamics (ABA) on a
// robot read from URDF, for comparison with our `urdf/forward_dynamics_talos`
// criterion benchmark on the same file. The model comes as Pinocchio's own
// binary serialization (written by pin_urdf_aba.sh with PyPI's `pin`, whose
// wheel lacks the urdfdom headers a C++ URDF parse needs). Fixed base,
// gravity 9.80665 along -z, zero joint torques, 64 random states with
// coordinates in [-1, 1], the median of 30 batches.
// Output: CSV `pinocchio-c++,aba_urdf,NV,median_ns` on stdout.
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>
#include <pinocchio/algorithm/aba.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s model.bin (a Pinocchio model saved by saveToBinary)\n", argv[0]);
    return 2;
  }
  pinocchio::Model model;
  model.loadFromBinary(argv[1]);
  model.gravity.linear(Eigen::Vector3d(0, 0, -9.80665));
  pinocchio::Data data(model);
  const int states = 64, batch = 2000;
  std::vector<Eigen::VectorXd> q, v;
  for (int k = 0; k < states; ++k) {
    q.push_back(Eigen::VectorXd::Random(model.nq));
    v.push_back(Eigen::VectorXd::Random(model.nv));
  }
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.nv);
  std::vector<double> per_call;
  double sink = 0;
  for (int round = 0; round < 30; ++round) {
    auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < batch; ++i) {
      int k = i % states;
      sink += pinocchio::aba(model, data, q[k], v[k], tau)[0];
    }
    auto ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    per_call.push_back(ns / batch);
  }
  std::sort(per_call.begin(), per_call.end());
  std::fprintf(stderr, "checksum %g\n", sink);
  std::printf("pinocchio-c++,aba_urdf,%d,%.1f\n", model.nv, per_call[per_call.size() / 2]);
}
