/// @file study_tables.cpp
/// @brief Table and series writers of `vid_massid elm-study` (seed tables 1-3).
#include "massid/elm/study_tables.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>

namespace vid::massid::elm {
namespace {

std::ofstream open_out(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  return out;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

std::string key_of(SweepKind kind, const StudyRow& r) {
  switch (kind) {
    case SweepKind::kHidden: return std::to_string(r.hidden);
    case SweepKind::kLambda: return fmt("%.0e", r.lambda);
    case SweepKind::kTrainingSets: return std::to_string(r.n_train);
    case SweepKind::kMethods: return r.method;
  }
  return "";
}

const char* key_name(SweepKind kind) {
  switch (kind) {
    case SweepKind::kHidden: return "hidden nodes";
    case SweepKind::kLambda: return "lambda";
    case SweepKind::kTrainingSets: return "training datasets";
    case SweepKind::kMethods: return "method";
  }
  return "";
}

}  // namespace

void write_study_table(const std::filesystem::path& dir, const std::string& stem,
                       const std::string& title, SweepKind kind,
                       const std::vector<StudyRow>& rows) {
  {
    const auto file = dir / (stem + ".csv");
    auto out = open_out(file);
    out << "trajectory,method,hidden,lambda,n_train,train_rows,train_s,weight_norm,"
           "train_rmse_pct,test_rmse_pct,test_rmse_full_pct,test_samples\n";
    for (const auto& r : rows) {
      out << r.trajectory << ',' << r.method << ',' << r.hidden << ',' << fmt("%.3g", r.lambda)
          << ',' << r.n_train << ',' << r.rows << ',' << fmt("%.4f", r.train_seconds) << ','
          << fmt("%.6g", r.weight_norm) << ',' << fmt("%.3f", r.train_rmse_percent) << ','
          << fmt("%.3f", r.test.rmse_percent) << ',' << fmt("%.3f", r.test.rmse_full_percent)
          << ',' << r.test.samples << '\n';
    }
    if (!out) throw std::runtime_error(file.string() + ": write failed");
  }
  const auto file = dir / (stem + ".md");
  auto out = open_out(file);
  out << "# " << title << "\n\n"
      << "RMSE = RMSPE (docs/model.md eq. (56)) [%] on held-out runs after the 1 s feature warm-up "
         "(in brackets: over every sample, warm-up at the initial guess); time = training wall "
         "clock [s] (features + hidden layer + output weights); |beta| = Frobenius norm of the "
         "output weights.\n";
  // Group by trajectory, keep first-seen order of keys and methods.
  std::vector<std::string> trajectories, methods;
  for (const auto& r : rows) {
    if (std::find(trajectories.begin(), trajectories.end(), r.trajectory) == trajectories.end())
      trajectories.push_back(r.trajectory);
    if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
      methods.push_back(r.method);
  }
  const bool per_method_columns = kind != SweepKind::kMethods;
  for (const auto& traj : trajectories) {
    out << "\n## " << traj << "\n\n| " << key_name(kind);
    std::vector<std::string> col_methods = per_method_columns ? methods : std::vector<std::string>{""};
    for (const auto& m : col_methods) {
      const std::string p = m.empty() ? "" : m + " ";
      out << " | " << p << "time [s] | " << p << "RMSE [%] | " << p << "|beta|";
    }
    out << " | train rows |\n|---";
    for (size_t i = 0; i < col_methods.size() * 3 + 1; ++i) out << "|---";
    out << "|\n";
    std::vector<std::string> keys;
    std::map<std::string, std::map<std::string, const StudyRow*>> table;
    for (const auto& r : rows) {
      if (r.trajectory != traj) continue;
      const std::string k = key_of(kind, r);
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
      table[k][per_method_columns ? r.method : ""] = &r;
    }
    for (const auto& k : keys) {
      out << "| " << k;
      long n_rows = 0;
      for (const auto& m : col_methods) {
        auto it = table[k].find(m);
        if (it == table[k].end()) {
          out << " | | |";
          continue;
        }
        const auto& r = *it->second;
        n_rows = r.rows;
        out << " | " << fmt("%.3f", r.train_seconds) << " | " << fmt("%.2f", r.test.rmse_percent)
            << " (" << fmt("%.2f", r.test.rmse_full_percent) << ") | "
            << fmt("%.4g", r.weight_norm);
      }
      out << " | " << n_rows << " |\n";
    }
  }
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

void write_series_csv(const std::filesystem::path& file, const MassIdRun& run,
                      const std::vector<std::string>& methods,
                      const std::vector<std::vector<double>>& estimates) {
  auto out = open_out(file);
  out << "t,mass_true";
  for (const auto& m : methods) out << ',' << m;
  out << '\n';
  for (size_t k = 0; k < run.samples.size(); ++k) {
    out << fmt("%.3f", run.samples[k].t) << ',' << fmt("%.6f", run.samples[k].mass_true);
    for (const auto& e : estimates) out << ',' << fmt("%.6f", e.at(k));
    out << '\n';
  }
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

}  // namespace vid::massid::elm
