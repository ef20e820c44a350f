// odonata-sim run as a real process: arguments, error exits, determinism and output layout.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "plant/output_signals.hpp"
#include "sim_runner.hpp"

namespace {

struct Result {
  int exit_code{};
  std::string out;
  std::string err;
};

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class SimCli : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/odonata_sim_test_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }

  Result Run(const std::string& args) const {
    const std::string out = dir_ + "/stdout", err = dir_ + "/stderr";
    const std::string cmd = std::string(ODONATA_SIM_EXE) + " " + args + " >" + out + " 2>" + err;
    const int status = std::system(cmd.c_str());
    return Result{WIFEXITED(status) ? WEXITSTATUS(status) : -1, Slurp(out), Slurp(err)};
  }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
  }

  std::string dir_;
};

TEST_F(SimCli, HelpAndListPresets) {
  const Result help = Run("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--preset"), std::string::npos);
  EXPECT_NE(help.out.find("--commands"), std::string::npos);
  const Result list = Run("--list-presets");
  EXPECT_EQ(list.exit_code, 0);
  for (const char* name :
       {"actuator_fz", "actuator_fx", "vertical_velocity", "roll", "pitch", "yaw"}) {
    EXPECT_NE(list.out.find(name), std::string::npos) << name;
  }
}

TEST_F(SimCli, UnknownPresetIsAClearError) {
  const Result r = Run("--preset rol --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown preset 'rol'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("roll"), std::string::npos) << r.err;  // lists the known ones
}

TEST_F(SimCli, BadArgumentsAreErrors) {
  EXPECT_EQ(Run("--preset roll --phase test --output " + Path("x.csv")).exit_code, 2);
  EXPECT_EQ(Run("--preset roll").exit_code, 2);              // no --output
  EXPECT_EQ(Run("--output " + Path("x.csv")).exit_code, 2);  // no source
  EXPECT_EQ(Run("--preset roll --duration -1 --output " + Path("x.csv")).exit_code, 2);
  EXPECT_EQ(Run("--preset roll --output /nonexistent/dir/x.csv").exit_code, 2);
}

TEST_F(SimCli, BadConfigurationIsAClearError) {
  Result r = Run("--preset roll --config " + Path("missing.json") + " --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos) << r.err;
  Write("broken.json", "{ \"mass_kg\": ");
  r = Run("--preset roll --config " + Path("broken.json") + " --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not valid JSON"), std::string::npos) << r.err;
  std::string text = Slurp(std::string(ODONATA_PLANT_CONFIG_DIR) + "/dimav_40g.json");
  text.replace(text.find("\"mass_kg\": 0.04"), 15, "\"mass_kg\": -0.04");
  Write("negative.json", text);
  r = Run("--preset roll --config " + Path("negative.json") + " --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("mass_kg"), std::string::npos) << r.err;
}

TEST_F(SimCli, BadCommandFileIsAClearError) {
  Write("nocols.csv", "t_s,w1_freq_hz\n0,5\n0.01,5\n");
  Result r = Run("--commands " + Path("nocols.csv") + " --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("w1_beta_rad"), std::string::npos) << r.err;
  EXPECT_EQ(Run("--commands " + Path("none.csv") + " --output " + Path("x.csv")).exit_code, 2);
}

TEST_F(SimCli, SameSeedGivesTheSameCsvBitForBit) {
  for (const char* preset : {"roll", "vertical_velocity", "actuator_fz"}) {
    const std::string base = std::string("--preset ") + preset + " --phase validate --duration 3";
    ASSERT_EQ(Run(base + " --seed 5 --output " + Path("a.csv")).exit_code, 0);
    ASSERT_EQ(Run(base + " --seed 5 --output " + Path("b.csv")).exit_code, 0);
    ASSERT_EQ(Run(base + " --seed 6 --output " + Path("c.csv")).exit_code, 0);
    EXPECT_EQ(Slurp(Path("a.csv")), Slurp(Path("b.csv"))) << preset;
    EXPECT_NE(Slurp(Path("a.csv")), Slurp(Path("c.csv"))) << preset;
  }
}

TEST_F(SimCli, DamagedWingFliesLessThanCommandedFromItsTimeOn) {
  const std::string base = "--preset actuator_fz --phase validate --seed 2 --duration 4 --output ";
  ASSERT_EQ(Run(base + Path("ok.csv")).exit_code, 0);
  const Result r =
      Run(base + Path("hurt.csv") + " --damage-at 2 --damage-wing 1 --damage-amplitude 0.7");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const odonata::io::CsvTable ok = odonata::io::CsvTable::Read(Path("ok.csv"));
  const odonata::io::CsvTable hurt = odonata::io::CsvTable::Read(Path("hurt.csv"));
  // Commands (what the identifier sees) are identical; wing 1's force is not, after 2 s only.
  EXPECT_EQ(ok.Column("w1_amp_rad"), hurt.Column("w1_amp_rad"));
  for (std::size_t k = 0; k <= 200; ++k) EXPECT_EQ(ok.Column("fz1_n")[k], hurt.Column("fz1_n")[k]);
  double ok_late = 0, hurt_late = 0;
  for (std::size_t k = 300; k < 400; ++k) {
    ok_late += ok.Column("fz1_n")[k];
    hurt_late += hurt.Column("fz1_n")[k];
  }
  EXPECT_LT(hurt_late, 0.7 * ok_late) << "lift falls faster than the amplitude";
  EXPECT_EQ(Run(base + Path("x.csv") + " --damage-at 1 --damage-wing 7").exit_code, 2);
}

TEST_F(SimCli, CsvHasTheDocumentedColumnsAndAnExcitationColumn) {
  ASSERT_EQ(Run("--preset roll --duration 2 --output " + Path("roll.csv")).exit_code, 0);
  const odonata::io::CsvTable t = odonata::io::CsvTable::Read(Path("roll.csv"));
  EXPECT_EQ(t.rows(), 200u);
  const std::vector<std::string> expected = odonata::sim::CsvHeader({"u_roll_rad"}, true);
  EXPECT_EQ(t.names(), expected);
  EXPECT_EQ(t.names()[1], "w1_beta_rad");
  EXPECT_EQ(t.names()[24], "w4_phase_rad");
  EXPECT_EQ(t.Column("t_s")[1], 0.01);
  EXPECT_EQ(t.Column("z_m")[0], 50.0);
  // The columns before the new ones keep their places: … fz4_n, then the excitation.
  EXPECT_EQ(t.names()[36], "z_m");
  EXPECT_EQ(t.names()[44], "fz4_n");
  EXPECT_EQ(t.names()[45], "u_roll_rad");
  // Then the beat averages, named after the instantaneous columns, and the applied channels.
  const std::vector<std::string> tail(t.names().begin() + 46, t.names().end());
  EXPECT_EQ(tail, (std::vector<std::string>{
                      "vx_mps_avg", "vy_mps_avg", "vz_mps_avg", "p_radps_avg", "q_radps_avg",
                      "r_radps_avg", "roll_rad_avg", "pitch_rad_avg", "yaw_rad_avg",
                      "fx_total_n_avg", "fz_total_n_avg", "u_vertical_applied_rad",
                      "u_roll_applied_rad", "u_pitch_applied_rad", "u_yaw_applied_rad"}));
  for (const std::string& name : odonata::plant::BeatSignalNames()) {
    if (name.rfind("f", 0) == 0) continue;  // the totals have no instantaneous column
    const std::string raw = name.substr(0, name.size() - 4);
    EXPECT_NEAR(t.Column(name)[0], t.Column(raw)[0], 1e-12) << name;  // the initial state
  }
  // A test-stand preset has no hold: no applied columns (its w{i}_* columns are applied).
  ASSERT_EQ(Run("--preset actuator_fz --duration 1 --output " + Path("fz.csv")).exit_code, 0);
  EXPECT_EQ(odonata::io::CsvTable::Read(Path("fz.csv")).names(), odonata::sim::CsvHeader({}));
}

double PairMean(const odonata::io::CsvTable& t, const char* a, const char* b, std::size_t k) {
  return 0.5 * (t.Column(a)[k] + t.Column(b)[k]);
}

// The applied columns are the excitation's channel of the command the wings actually got (the
// w{i}_* columns): for roll and pitch that adds the hold's correction to the excitation; yaw's
// stroke-plane angles and the four-wing mean amplitude are untouched by the hold.
TEST_F(SimCli, AppliedColumnsAreTheChannelsOfTheAppliedCommand) {
  for (const char* preset : {"roll", "pitch", "yaw", "vertical_velocity"}) {
    SCOPED_TRACE(preset);
    const std::string csv = Path(std::string(preset) + ".csv");
    ASSERT_EQ(Run(std::string("--preset ") + preset + " --duration 10 --output " + csv).exit_code,
              0);
    const odonata::io::CsvTable t = odonata::io::CsvTable::Read(csv);
    const std::string channel = preset == std::string("vertical_velocity") ? "vertical" : preset;
    const std::vector<double>& u = t.Column("u_" + channel + "_rad");
    const std::vector<double>& applied = t.Column("u_" + channel + "_applied_rad");
    double max_gap = 0.0;
    for (std::size_t k = 0; k < t.rows(); ++k) {
      const double left = PairMean(t, "w1_amp_rad", "w2_amp_rad", k);
      const double right = PairMean(t, "w3_amp_rad", "w4_amp_rad", k);
      const double front = PairMean(t, "w1_amp_rad", "w4_amp_rad", k);
      const double back = PairMean(t, "w2_amp_rad", "w3_amp_rad", k);
      const double beta_left = PairMean(t, "w1_beta_rad", "w2_beta_rad", k);
      const double beta_right = PairMean(t, "w3_beta_rad", "w4_beta_rad", k);
      ASSERT_NEAR(t.Column("u_roll_applied_rad")[k], 0.5 * (left - right), 1e-12) << k;
      ASSERT_NEAR(t.Column("u_pitch_applied_rad")[k], 0.5 * (front - back), 1e-12) << k;
      ASSERT_NEAR(t.Column("u_yaw_applied_rad")[k], 0.5 * (beta_right - beta_left), 1e-12) << k;
      max_gap = std::max(max_gap, std::fabs(applied[k] - u[k]));
    }
    if (channel == "roll" || channel == "pitch") {
      EXPECT_GT(max_gap, 1e-4);  // the hold acts on this channel
    } else {
      EXPECT_LT(max_gap, 1e-12);  // and not on these
    }
  }
}

// Averaged over the wing beat, vertical velocity loses the ripple at twice the flapping
// frequency: its sample-to-sample changes shrink far more than the slow response does.
TEST_F(SimCli, BeatAveragedVelocityHasNoWingBeatRipple) {
  ASSERT_EQ(Run("--preset vertical_velocity --duration 10 --output " + Path("v.csv")).exit_code, 0);
  const odonata::io::CsvTable t = odonata::io::CsvTable::Read(Path("v.csv"));
  const auto rms_diff = [&t](const std::string& name) {
    const std::vector<double>& v = t.Column(name);
    double sum = 0.0;
    for (std::size_t k = 1; k < v.size(); ++k) sum += (v[k] - v[k - 1]) * (v[k] - v[k - 1]);
    return std::sqrt(sum / static_cast<double>(v.size() - 1));
  };
  EXPECT_LT(rms_diff("vz_mps_avg"), 0.3 * rms_diff("vz_mps"));
}

// --decimate N: one row per N samples, outputs at the block's first sample, inputs averaged over
// the block.
TEST_F(SimCli, DecimateKeepsOutputsAndAveragesInputsOverEachBlock) {
  const std::string base = "--preset roll --duration 3 --output ";
  ASSERT_EQ(Run(base + Path("full.csv")).exit_code, 0);
  ASSERT_EQ(Run(base + Path("dec.csv") + " --decimate 19").exit_code, 0);
  ASSERT_EQ(Run(base + Path("one.csv") + " --decimate 1").exit_code, 0);
  EXPECT_EQ(Slurp(Path("one.csv")), Slurp(Path("full.csv")));
  EXPECT_EQ(Run(base + Path("x.csv") + " --decimate 0").exit_code, 2);
  const odonata::io::CsvTable full = odonata::io::CsvTable::Read(Path("full.csv"));
  const odonata::io::CsvTable dec = odonata::io::CsvTable::Read(Path("dec.csv"));
  ASSERT_EQ(dec.names(), full.names());
  ASSERT_EQ(dec.rows(), 300u / 19u);  // the partial last block is dropped
  for (std::size_t j = 0; j < dec.rows(); ++j) {
    for (const char* out : {"t_s", "roll_rad", "vz_mps", "roll_rad_avg", "fz_total_n_avg"}) {
      EXPECT_EQ(dec.Column(out)[j], full.Column(out)[19 * j]) << out << " " << j;
    }
    for (const char* in : {"w1_amp_rad", "u_roll_rad", "u_roll_applied_rad"}) {
      double sum = 0.0;
      for (std::size_t k = 19 * j; k < 19 * j + 19; ++k) sum += full.Column(in)[k];
      EXPECT_NEAR(dec.Column(in)[j], sum / 19.0, 1e-12) << in << " " << j;
    }
  }
}

TEST_F(SimCli, SelectPhaseIsAThirdExcitation) {
  const std::string base = "--preset pitch --duration 3 --seed 4 --phase ";
  ASSERT_EQ(Run(base + "train --output " + Path("t.csv")).exit_code, 0);
  ASSERT_EQ(Run(base + "select --output " + Path("s.csv")).exit_code, 0);
  ASSERT_EQ(Run(base + "validate --output " + Path("v.csv")).exit_code, 0);
  const std::string train = Slurp(Path("t.csv")), select = Slurp(Path("s.csv")),
                    val = Slurp(Path("v.csv"));
  EXPECT_NE(select, train);
  EXPECT_NE(select, val);
  EXPECT_EQ(odonata::io::CsvTable::Read(Path("s.csv")).rows(), 300u);
  const Result help = Run("--help");
  EXPECT_NE(help.out.find("select"), std::string::npos);
}

// A CSV written by the simulator is itself a valid command file; replaying its commands without
// the attitude hold (already inside the recorded commands) reproduces the run exactly.
TEST_F(SimCli, CommandFileReplaysARecordedRun) {
  ASSERT_EQ(Run("--preset yaw --duration 2 --output " + Path("yaw.csv")).exit_code, 0);
  ASSERT_EQ(Run("--commands " + Path("yaw.csv") + " --output " + Path("replay.csv")).exit_code, 0);
  const odonata::io::CsvTable a = odonata::io::CsvTable::Read(Path("yaw.csv"));
  const odonata::io::CsvTable b = odonata::io::CsvTable::Read(Path("replay.csv"));
  ASSERT_EQ(a.rows(), b.rows());
  for (const char* col : {"yaw_rad", "roll_rad", "vz_mps", "fz1_n"}) {
    EXPECT_EQ(a.Column(col), b.Column(col)) << col;
  }
}

TEST_F(SimCli, NonUniformTimeInCommandFileIsRejected) {
  ASSERT_EQ(Run("--preset yaw --duration 1 --output " + Path("yaw.csv")).exit_code, 0);
  std::string text = Slurp(Path("yaw.csv"));
  const std::size_t pos = text.find("\n0.02");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 5, "\n0.025");
  Write("bad_t.csv", text);
  const Result r = Run("--commands " + Path("bad_t.csv") + " --output " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sample period"), std::string::npos) << r.err;
}

// A manoeuvre that tumbles the vehicle (±0.35 rad of stroke amplitude, left against right): with
// the default policy "stop" the simulator says what diverged and when, exits 3, and the CSV holds
// the rows up to the divergence, every one of them finite.
TEST_F(SimCli, DivergenceStopsWithAClearMessageAndNoNaN) {
  ASSERT_EQ(Run("--preset roll --duration 1 --output " + Path("roll.csv")).exit_code, 0);
  const odonata::io::CsvTable roll = odonata::io::CsvTable::Read(Path("roll.csv"));
  const std::vector<std::string> names(roll.names().begin(), roll.names().begin() + 25);
  ASSERT_EQ(names.front(), "t_s");
  {
    odonata::io::CsvWriter out(Path("tumble.csv"), names);
    for (std::size_t r = 0; r < roll.rows(); ++r) {
      std::vector<double> row;
      for (const std::string& name : names) {
        double v = roll.Column(name)[r];
        if (name == "w1_amp_rad" || name == "w2_amp_rad") v += 0.35;
        if (name == "w3_amp_rad" || name == "w4_amp_rad") v -= 0.35;
        row.push_back(v);
      }
      out.WriteRow(row);
    }
    out.Close();
  }
  const Result r = Run("--commands " + Path("tumble.csv") + " --output " + Path("t.csv"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("max_tilt_rad"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
  const odonata::io::CsvTable t = odonata::io::CsvTable::Read(Path("t.csv"));  // throws on NaN
  EXPECT_GT(t.rows(), 0u);
  EXPECT_LT(t.rows(), roll.rows());
}

// Every preset, all three phases, full length: no divergence, no NaN (exit code 0).
TEST_F(SimCli, FullLengthPresetsRunWithoutDivergence) {
  for (const char* preset :
       {"actuator_fz", "actuator_fx", "vertical_velocity", "roll", "pitch", "yaw"}) {
    for (const char* phase : {"train", "select", "validate"}) {
      const Result r = Run(std::string("--preset ") + preset + " --phase " + phase + " --output " +
                           Path("full.csv"));
      EXPECT_EQ(r.exit_code, 0) << preset << " " << phase << ": " << r.err;
    }
  }
}

}  // namespace
