// Writes what octave_fis_test.sh checks Octave against: a trained Narendra model (model.json),
// 1000 validation regressors (inputs.csv, raw units, no header) and odonata's outputs on them
// (expected.csv), into the directory given as the only argument.

#include <cstdio>
#include <fstream>
#include <iostream>

#include "trained_narendra_model.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_fixture DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  using namespace odonata;
  const sysid::NarxModel m = model_export::testing::TrainedNarendraModel();
  m.Save(dir + "/model.json");
  const auto data = sysid::BuildRegression(m.spec(), sysid::testing::NarendraValidate(1001));
  std::ofstream in(dir + "/inputs.csv"), out(dir + "/expected.csv");
  char buf[64];
  for (Eigen::Index t = 0; t < 1000; ++t) {
    const Eigen::VectorXd x = data.x.row(t).transpose();
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : "", x(i));
      in << buf;
    }
    std::snprintf(buf, sizeof buf, "%.17g", m.Predict(x)(0));
    in << "\n";
    out << buf << "\n";
  }
  std::cout << m.total_rules() << " rules\n";
  return in && out ? 0 : 1;
}
