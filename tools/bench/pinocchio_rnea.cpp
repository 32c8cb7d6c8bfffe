// Pinocchio's RNEA time per call in C++ (no Python binding in the loop): the companion of
// pinocchio_rnea.py, which writes the robots' Pinocchio models (Model::saveToText, the same models as
// golden/make_golden_arms.py builds), compiles this file against the pip-installed Pinocchio and runs it.
// Usage: pinocchio_rnea_cpp CALLS REPS NAME MODEL.txt [NAME MODEL.txt]...
// Prints one line per robot: name, joints, median and fastest repetition's us per call, sum of tau at a fixed sample
// (cross-checked against Python), and a value that keeps the timed loop from being optimised away.
// Build (pinocchio_rnea.py --cpp does this): header-only Pinocchio, Eigen from Debian's libeigen3-dev,
//   g++ -O3 -std=c++17 -DNDEBUG -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
//       -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -I$PREFIX/include
//       -I/usr/include/eigen3 pinocchio_rnea.cpp -o pinocchio_rnea_cpp -L$PREFIX/lib -Wl,-rpath,$PREFIX/lib
//       -lboost_serialization        (PREFIX = site-packages/cmeel.prefix of the venv)
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace pin = pinocchio;

static void bench(const std::string& name, const pin::Model& model, long calls, int reps) {
  pin::Data data(model);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(-3.141592653589793, 3.141592653589793), unit(-1.0, 1.0);
  const int batch = 1000;
  std::vector<Eigen::VectorXd> q(batch), v(batch), a(batch);
  for (int i = 0; i < batch; ++i) {
    q[i] = Eigen::VectorXd(model.nq), v[i] = Eigen::VectorXd(model.nv), a[i] = Eigen::VectorXd(model.nv);
    for (int j = 0; j < model.nv; ++j) q[i][j] = angle(rng), v[i][j] = unit(rng), a[i][j] = unit(rng);
  }
  const long rounds = std::max(1L, calls / batch);
  std::vector<double> per_call;
  double sink = 0.0;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < rounds; ++k)
      for (int i = 0; i < batch; ++i) sink += pin::rnea(model, data, q[i], v[i], a[i])[0];
    const std::chrono::duration<double> dt = std::chrono::steady_clock::now() - t0;
    per_call.push_back(dt.count() / double(rounds * batch));
  }
  std::sort(per_call.begin(), per_call.end());
  // tau at a fixed sample (q_j = 0.1 j, v_j = 0.2, a_j = -0.3 in Pinocchio's vectors) for the cross-check
  Eigen::VectorXd qc(model.nq), vc = Eigen::VectorXd::Constant(model.nv, 0.2), ac = Eigen::VectorXd::Constant(model.nv, -0.3);
  for (int j = 0; j < model.nq; ++j) qc[j] = 0.1 * (j + 1);
  const Eigen::VectorXd tau = pin::rnea(model, data, qc, vc, ac);
  std::printf("%s %d %.6f %.6f %.17g %.17g\n", name.c_str(), model.nv, per_call[per_call.size() / 2] * 1e6,
              per_call.front() * 1e6, tau.sum(),
              sink == 42.0 ? 1.0 : 0.0);
}

int main(int argc, char** argv) {
  if (argc < 5 || (argc - 3) % 2 != 0) {
    std::fprintf(stderr, "usage: %s CALLS REPS NAME MODEL.txt [NAME MODEL.txt]...\n", argv[0]);
    return 2;
  }
  const long calls = std::atol(argv[1]);
  const int reps = std::atoi(argv[2]);
  for (int k = 3; k < argc; k += 2) {
    pin::Model model;
    model.loadFromText(argv[k + 1]);
    bench(argv[k], model, calls, reps);
  }
  return 0;
}
