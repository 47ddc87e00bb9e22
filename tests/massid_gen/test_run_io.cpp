/// @file test_run_io.cpp
/// @brief Run CSV and manifest.yaml: exact round trips and errors that name file, line, field/key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

#include "massid/gen/manifest.h"
#include "massid/filters/study_io.h"
#include "massid/gen/study_config.h"
#include "massid/run_data.h"

namespace fs = std::filesystem;
using vid::massid::MassIdSample;
using vid::massid::RunInfo;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("massid_gen_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<MassIdSample> random_samples(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<MassIdSample> out;
  for (int k = 0; k < n; ++k) {
    MassIdSample s;
    s.t = 0.01 * k + 1e-13 * u(rng);  // awkward decimals
    s.q_WI = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
    s.p_WI = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1e3;
    s.v_WI = Eigen::Vector3d(u(rng), 1e-300, -u(rng) / 3.0);
    s.thrust_cmd = std::abs(u(rng)) + 1.0 / 3.0;
    s.w_I = Eigen::Vector3d(u(rng), u(rng), 0.1);
    s.mass_true = 1.0 + std::abs(u(rng)) / 7.0;
    out.push_back(s);
  }
  return out;
}

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

std::string error_of(const fs::path& file) {
  try {
    vid::massid::read_run_csv(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

const char* kHeader = "t,qw,qx,qy,qz,px,py,pz,vx,vy,vz,thrust_cmd,wx,wy,wz,mass_true\n";
const char* kGoodRow = "0.01,1,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,1.25\n";

}  // namespace

TEST(MassIdRunCsv, RoundTripIsBitExact) {
  const fs::path dir = temp_dir("roundtrip");
  const auto samples = random_samples(500, 7);
  vid::massid::write_run_csv(dir / "run.csv", samples);
  const auto back = vid::massid::read_run_csv(dir / "run.csv");
  ASSERT_EQ(back.size(), samples.size());
  for (size_t k = 0; k < samples.size(); ++k) {
    const MassIdSample& a = samples[k];
    const MassIdSample& b = back[k];
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.q_WI.coeffs(), b.q_WI.coeffs());
    EXPECT_EQ(a.p_WI, b.p_WI);
    EXPECT_EQ(a.v_WI, b.v_WI);
    EXPECT_EQ(a.thrust_cmd, b.thrust_cmd);
    EXPECT_EQ(a.w_I, b.w_I);
    EXPECT_EQ(a.mass_true, b.mass_true);
  }
  // Writing what was read gives the same bytes.
  vid::massid::write_run_csv(dir / "again.csv", back);
  std::ifstream f1(dir / "run.csv"), f2(dir / "again.csv");
  const std::string s1((std::istreambuf_iterator<char>(f1)), {});
  const std::string s2((std::istreambuf_iterator<char>(f2)), {});
  EXPECT_EQ(s1, s2);
  EXPECT_EQ(s1.substr(0, s1.find('\n') + 1), kHeader);
  fs::remove_all(dir);
}

TEST(MassIdRunCsv, BadFieldNamesFileLineAndField) {
  const fs::path dir = temp_dir("bad");
  const fs::path file = dir / "bad.csv";
  write_text(file, std::string(kHeader) + kGoodRow +
                       "0.02,1,0,0,0,1,abc,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,1.25\n");
  const std::string err = error_of(file);
  EXPECT_NE(err.find(file.string() + ":3:"), std::string::npos) << err;
  EXPECT_NE(err.find("'py'"), std::string::npos) << err;
  EXPECT_NE(err.find("abc"), std::string::npos) << err;
  fs::remove_all(dir);
}

TEST(MassIdRunCsv, WrongFieldCountsAndValuesAreRejected) {
  const fs::path dir = temp_dir("counts");
  const fs::path file = dir / "bad.csv";
  struct Case {
    std::string row, line_tag, what;
  };
  const std::vector<Case> cases = {
      {"0.02,1,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03\n", ":3:", "mass_true"},
      {"0.02,1,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,1.2,7\n", ":3:", "too many"},
      {"0.02,1,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,-1\n", ":3:", "mass_true"},
      {"0.02,1,0,0,0,1,2,3,0.1,0.2,0.3,-2,0.01,0.02,0.03,1.2\n", ":3:", "thrust_cmd"},
      {"0.02,2,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,1.2\n", ":3:", "quaternion"},
      {"0.01,1,0,0,0,1,2,3,0.1,0.2,0.3,12.5,0.01,0.02,0.03,1.2\n", ":3:", "'t'"},
      {"0.02,1,0,0,0,1,2,3,nan,0.2,0.3,12.5,0.01,0.02,0.03,1.2\n", ":3:", "'vx'"},
      {"0.02,1,0,0,0,1,2,3,,0.2,0.3,12.5,0.01,0.02,0.03,1.2\n", ":3:", "'vx'"},
  };
  for (const Case& c : cases) {
    write_text(file, std::string(kHeader) + kGoodRow + c.row);
    const std::string err = error_of(file);
    EXPECT_NE(err.find(file.string() + c.line_tag), std::string::npos) << c.row << " -> " << err;
    EXPECT_NE(err.find(c.what), std::string::npos) << c.row << " -> " << err;
  }
  write_text(file, "time,qw\n");
  EXPECT_NE(error_of(file).find(file.string() + ":1:"), std::string::npos);
  write_text(file, "");
  EXPECT_NE(error_of(file).find(file.string() + ":1:"), std::string::npos);
  EXPECT_THROW(vid::massid::read_run_csv(dir / "missing.csv"), std::runtime_error);
  fs::remove_all(dir);
}

TEST(MassIdManifest, RoundTripAndLayout) {
  const fs::path dir = temp_dir("manifest");
  std::vector<RunInfo> runs;
  for (int i = 0; i < 3; ++i) {
    RunInfo r;
    r.trajectory = i == 2 ? "square" : "loop";
    r.mass_profile = "step_drop";
    r.index = i;
    r.seed = 0xFFFFFFFFFFFFFFF0ull - static_cast<std::uint64_t>(i);  // full 64-bit range
    r.gravity = 9.80665;
    r.initial_mass_guess = 1.2 * (1.0 + i / 3.0);
    r.sigma_q = 0.005;
    r.sigma_p = 0.01 / 3.0;
    r.sigma_v = 0.02;
    runs.push_back(r);
  }
  vid::massid::gen::GeneratorSettings settings;
  settings.runs = 3;
  vid::massid::gen::write_manifest(dir, vid::massid::gen::generator_settings_yaml(settings), runs);
  const auto index = vid::massid::read_dataset_index(dir);
  EXPECT_EQ(index.root, dir);
  ASSERT_EQ(index.runs.size(), runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunInfo& a = runs[i];
    const RunInfo& b = index.runs[i];
    EXPECT_EQ(a.trajectory, b.trajectory);
    EXPECT_EQ(a.mass_profile, b.mass_profile);
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.gravity, b.gravity);
    EXPECT_EQ(a.initial_mass_guess, b.initial_mass_guess);
    EXPECT_EQ(a.sigma_q, b.sigma_q);
    EXPECT_EQ(a.sigma_p, b.sigma_p);
    EXPECT_EQ(a.sigma_v, b.sigma_v);
  }
  EXPECT_EQ(vid::massid::run_csv_path(dir, runs[2]), dir / "square" / "step_drop" / "run_002.csv");

  // load_run reads the CSV at that path.
  fs::create_directories(dir / "loop" / "step_drop");
  const auto samples = random_samples(10, 3);
  vid::massid::write_run_csv(vid::massid::run_csv_path(dir, runs[1]), samples);
  const auto run = vid::massid::load_run(index, index.runs[1]);
  EXPECT_EQ(run.info.index, 1);
  ASSERT_EQ(run.samples.size(), 10u);
  EXPECT_EQ(run.samples[9].p_WI, samples[9].p_WI);
  fs::remove_all(dir);
}

TEST(MassIdManifest, ErrorsNameFileAndKey) {
  const fs::path dir = temp_dir("manifest_bad");
  const fs::path file = dir / "manifest.yaml";
  auto error_for = [&](const std::string& text) {
    write_text(file, text);
    try {
      vid::massid::read_dataset_index(dir);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string head = "format: vid_massid_dataset\nversion: 1\n";
  std::string err = error_for(head + "runs:\n  - {trajectory: loop, mass_profile: constant, index: 0, "
                                     "seed: 1, gravity: 9.81, initial_mass_guess: 1.2, sigma_q: 0, "
                                     "sigma_p: 0}\n");
  EXPECT_NE(err.find(file.string()), std::string::npos) << err;
  EXPECT_NE(err.find("runs[0].sigma_v"), std::string::npos) << err;
  err = error_for(head + "runs:\n  - {trajectory: loop, mass_profile: constant, index: 0, "
                         "seed: 1, gravity: 9.81, initial_mass_guess: heavy, sigma_q: 0, "
                         "sigma_p: 0, sigma_v: 0}\n");
  EXPECT_NE(err.find("runs[0].initial_mass_guess"), std::string::npos) << err;
  err = error_for("format: something_else\nversion: 1\nruns: []\n");
  EXPECT_NE(err.find("'format'"), std::string::npos) << err;
  err = error_for(head);
  EXPECT_NE(err.find("'runs'"), std::string::npos) << err;
  fs::remove(file);
  EXPECT_THROW(vid::massid::read_dataset_index(dir), std::runtime_error);
  fs::remove_all(dir);
}

TEST(MassIdStudyConfig, YamlRoundTripAndUnknownKeys) {
  vid::massid::gen::GeneratorSettings s;
  s.runs = 7;
  s.seed = 123456789012345ull;
  s.sigma_p = 0.1 / 3.0;
  s.trajectories = {"loop", "square"};
  s.mass.up_down_times_s = {1.5, 2.5};
  s.controller.horizon = 12;
  const auto back = vid::massid::gen::parse_generator_settings(
      vid::massid::gen::generator_settings_yaml(s), "mem");
  EXPECT_EQ(back.runs, 7);
  EXPECT_EQ(back.seed, s.seed);
  EXPECT_EQ(back.sigma_p, s.sigma_p);
  EXPECT_EQ(back.trajectories, s.trajectories);
  EXPECT_EQ(back.mass.up_down_times_s, s.mass.up_down_times_s);
  EXPECT_EQ(back.controller.horizon, 12);
  EXPECT_EQ(vid::massid::gen::generator_settings_yaml(back), vid::massid::gen::generator_settings_yaml(s));
  EXPECT_TRUE(back == s);  // parse(print(x)) == x
  auto changed = s;
  changed.controller.weight_v *= 1.5;
  EXPECT_FALSE(changed == s);
  changed = s;
  changed.trajectories.pop_back();
  EXPECT_FALSE(changed == s);

  auto error_for = [](const std::string& text) {
    try {
      vid::massid::gen::parse_generator_settings(text, "study.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_for("runz: 3\n").find("study.yaml: key 'runz'"), std::string::npos);
  EXPECT_NE(error_for("controller:\n  horizn: 3\n").find("'controller.horizn'"), std::string::npos);
  EXPECT_NE(error_for("runs: many\n").find("'runs'"), std::string::npos);
  EXPECT_NE(error_for("trajectories: [loop, circle]\n").find("circle"), std::string::npos);
  // The shipped study file parses and is the documented study: 5 x 5 x 50 runs.
  const auto study = vid::massid::gen::load_generator_settings(VID_SOURCE_DIR "/config/massid/study.yaml");
  EXPECT_EQ(study.trajectories.size() * study.profiles.size() * study.runs, 1250u);
}

TEST(MassIdRunsCsv, ReadsRowsAndNamesFileLineAndField) {
  const fs::path dir = temp_dir("runs_csv");
  const fs::path file = dir / "runs.csv";
  const std::string head = vid::massid::runs_csv_header() + "\n";
  write_text(file, head + "loop,constant,0,7,ekf,100,1.5,0.01,0.02\nloop,constant,1,8,ukf,100,nan,0.01,0.02\n");
  const auto rows = vid::massid::read_runs_csv(file);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].method, "ekf");
  EXPECT_EQ(rows[0].rmspe_pct, 1.5);
  EXPECT_TRUE(std::isnan(rows[1].rmspe_pct));  // a diverged run stays in the tables as before
  auto error_of = [&](const std::string& text) {
    write_text(file, text);
    try {
      vid::massid::read_runs_csv(file);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of(head + "loop,constant,0,7,ekf,many,1.5,0.01,0.02\n")
                .find(file.string() + ":2: column 6 'samples': expected an integer, got 'many'"),
            std::string::npos);
  EXPECT_NE(error_of(head + "loop,constant,0,7,ekf\n").find(file.string() + ":2: expected 9 columns"), std::string::npos);
  EXPECT_NE(error_of("trajectory,profile\n").find(file.string() + ":1: bad header"), std::string::npos);
  EXPECT_NE(error_of(head).find("no rows"), std::string::npos);
  fs::remove_all(dir);
}
