/// @file main.cpp
/// @brief vid_info DATASET [--json]: read a dataset folder end to end (images are only checked
/// for existence, never decoded) and print per-stream counts, rates, spans and largest gaps.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "app/cli.h"
#include "app/run_main.h"
#include "io/dataset_reader.h"
#include "summary.h"
#include "vid_system/progress.h"

int main(int argc, char** argv) {
  return vid::app::run_main("vid_info", [&]() -> int {
    CLI::App cli{"Summarise a dataset folder (EuRoC/ASL + extensions): streams, counts, rates, time span, "
                 "largest gaps, dropped rows and calibration found."};
    std::string dataset;
    bool json = false;
    vid::io::ReaderOptions options;
    options.max_gap_periods = 0.0;  // a summary: gaps are reported (largest gap per stream), not errors
    cli.add_option("DATASET", dataset, "dataset folder (SEQ or SEQ/mav0)")->required();
    cli.add_flag("--json", json, "machine-readable JSON on stdout");
    cli.add_flag("--drop-bad-timestamps", options.drop_bad_timestamps,
                 "drop non-monotonic/duplicate rows (counted) instead of failing");
    cli.add_flag("--skip-missing-images", options.skip_missing_images,
                 "skip listed images that are missing (counted) instead of failing");
    if (const auto code = vid::app::parse_cli(cli, argc, argv)) return *code;

    vid::io::DatasetReader reader(dataset, options);
    vid::system::ProgressBar bar("vid_info", 1.0);
    std::size_t n = 0;
    while (reader.next()) {
      if (++n % 4096 == 0) bar.update(reader.progress());
    }
    bar.finish();

    vid::app::DatasetSummary summary{reader.mav0().string(), reader.stats(), reader.calibration()};
    const std::string text = json ? vid::app::summary_json(summary) : vid::app::summary_text(summary);
    std::fputs(text.c_str(), stdout);
    return 0;
  });
}
