/// @file test_determinism.cpp
/// @brief Same seed -> byte-identical run CSVs and manifest, for any thread count and through
/// the `vid_massid generate` program; the program reports bad settings with one line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <algorithm>

#include "massid/gen/dataset_generator.h"
#include "massid/run_data.h"

namespace fs = std::filesystem;
using namespace vid::massid::gen;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("massid_det_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Relative path -> contents of every file under dir.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = slurp(e.path());
  }
  return out;
}

GeneratorSettings small_settings() {
  GeneratorSettings s;
  s.trajectories = {"random", "lemniscate"};
  s.profiles = {"step_drop", "up_down"};
  s.runs = 3;
  s.duration_s = 4.0;
  return s;
}

}  // namespace

TEST(MassIdDeterminism, SameSeedSameBytesAnyThreadCount) {
  const fs::path a = temp_dir("a"), b = temp_dir("b"), c = temp_dir("c");
  const GeneratorSettings s = small_settings();
  const auto ra = generate_dataset(s, a, 1);
  generate_dataset(s, b, 2);
  GeneratorSettings other = s;
  other.seed += 1;
  generate_dataset(other, c, 2);
  const auto ta = tree(a), tb = tree(b), tc = tree(c);
  ASSERT_EQ(ta.size(), 2u * 2u * 3u + 1u);  // runs + manifest
  EXPECT_EQ(ta, tb);
  ASSERT_EQ(tc.size(), ta.size());
  for (const auto& [name, text] : ta) {
    if (name != "manifest.yaml") {
      EXPECT_NE(text, tc.at(name)) << name;
    }
  }
  // The manifest indexes exactly the written runs, and they load.
  const auto index = vid::massid::read_dataset_index(a);
  ASSERT_EQ(index.runs.size(), 12u);
  for (const auto& info : index.runs) {
    const auto run = vid::massid::load_run(index, info);
    EXPECT_EQ(run.samples.size(), 401u);
    EXPECT_NEAR(info.initial_mass_guess, s.initial_mass_factor * run.samples.front().mass_true, 1e-12);
  }
  EXPECT_EQ(ra.groups.size(), 4u);
  for (const fs::path& d : {a, b, c}) fs::remove_all(d);
}

TEST(MassIdDeterminism, SubsetGeneratesTheSameRunsAsTheFullStudy) {
  const fs::path a = temp_dir("full"), b = temp_dir("subset");
  GeneratorSettings s = small_settings();
  generate_dataset(s, a, 2);
  s.trajectories = {"lemniscate"};
  s.profiles = {"up_down"};
  s.runs = 2;
  generate_dataset(s, b, 1);
  for (int i = 0; i < 2; ++i) {
    const std::string rel = "lemniscate/up_down/run_00" + std::to_string(i) + ".csv";
    EXPECT_EQ(slurp(a / rel), slurp(b / rel)) << rel;
  }
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(MassIdDeterminism, ProgramIsDeterministicAndRejectsBadSettings) {
  const std::string exe = std::string(VID_BINARY_DIR) + "/bin/vid_massid";
  const fs::path a = temp_dir("cli_a"), b = temp_dir("cli_b"), cfg_dir = temp_dir("cli_cfg");
  const fs::path cfg = cfg_dir / "study.yaml";
  std::ofstream(cfg) << "runs: 2\nduration_s: 3\n";
  const std::string common = " generate --config " + cfg.string() +
                             " --trajectories loop,square --profiles constant,step_pickup --seed 5 --quiet";
  ASSERT_EQ(std::system((exe + common + " --threads 2 --out " + a.string() + " 2>/dev/null").c_str()), 0);
  ASSERT_EQ(std::system((exe + common + " --threads 1 --out " + b.string() + " 2>/dev/null").c_str()), 0);
  const auto ta = tree(a);
  EXPECT_EQ(ta.size(), 2u * 2u * 2u + 1u);
  EXPECT_EQ(ta, tree(b));

  std::ofstream(cfg) << "runs: 2\ncontroler: {horizon: 3}\n";
  const fs::path err = cfg_dir / "err.txt";
  const int rc = std::system((exe + " generate --config " + cfg.string() + " --out " +
                              (cfg_dir / "x").string() + " 2>" + err.string()).c_str());
  EXPECT_NE(rc, 0);
  const std::string msg = slurp(err);
  EXPECT_NE(msg.find(cfg.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("controler"), std::string::npos) << msg;
  EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 1) << msg;
  for (const fs::path& d : {a, b, cfg_dir}) fs::remove_all(d);
}

TEST(MassIdDeterminism, TruthCompanionOnRequestOnly) {
  const fs::path a = temp_dir("truth"), b = temp_dir("no_truth");
  GeneratorSettings s = small_settings();
  s.trajectories = {"lemniscate"};
  s.profiles = {"constant"};
  s.runs = 1;
  generate_dataset(s, a, 1, {}, true);
  generate_dataset(s, b, 1);
  const fs::path truth = a / "lemniscate/constant/run_000_truth.csv";
  ASSERT_TRUE(fs::exists(truth));
  EXPECT_FALSE(fs::exists(b / "lemniscate/constant/run_000_truth.csv"));
  EXPECT_EQ(slurp(a / "lemniscate/constant/run_000.csv"), slurp(b / "lemniscate/constant/run_000.csv"));
  const std::string text = slurp(truth);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 402);  // header + 401 samples
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "t,px,py,pz,qw,qx,qy,qz,vx,vy,vz,px_ref,py_ref,pz_ref,ax_cmd,ay_cmd,az_cmd,saturated");
  fs::remove_all(a);
  fs::remove_all(b);
}
