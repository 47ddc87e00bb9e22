/// @file main.cpp
/// @brief vid_massid: the mass-identification study (seed sections 4-6) — generate data,
/// run the methods, write the tables and plots.
#include <CLI/CLI.hpp>

#include "app/cli.h"
#include "app/run_main.h"
#include "commands.h"

int main(int argc, char** argv) {
  return vid::app::run_main("vid_massid", [&]() -> int {
    CLI::App cli{"Mass-identification study: simulate a quadrotor whose mass changes in flight, "
                 "identify the mass with EKF/MSCKF/UKF/SWLS/ELM/RELM/OSELM, report RMSPE and "
                 "update times."};
    cli.require_subcommand(1);
    int exit_code = 0;
    vid::massid_app::add_generate_command(cli, &exit_code);
    vid::massid_app::add_run_report_commands(cli, &exit_code);
    vid::massid_app::add_elm_study_command(cli, &exit_code);
    vid::massid_app::add_from_sequence_command(cli, &exit_code);
    // CLI11 says only "A subcommand is required" for a mistyped one: name it.
    if (argc > 1 && argv[1][0] != '-') {
      const std::string name = argv[1];
      if (cli.get_subcommands([&](CLI::App* s) { return s->check_name(name); }).empty())
        throw vid::system::UsageError("unknown subcommand '" + name + "' (see --help)");
    }
    if (const auto code = vid::app::parse_cli(cli, argc, argv)) return *code;
    return exit_code;
  });
}
