#pragma once
// Each command group adds its subcommands to the program here. A subcommand's callback
// throws rostro::InputError for bad input; main() turns that into one line and exit 1.

#include <CLI/CLI.hpp>

namespace rostro::app {

void add_fap_commands(CLI::App& app);
void add_devices_commands(CLI::App& app);
void add_eval_commands(CLI::App& app);
void add_synth_commands(CLI::App& app);
void add_play_commands(CLI::App& app);
void add_track_commands(CLI::App& app);
void add_speech_commands(CLI::App& app);
void add_script_commands(CLI::App& app);
void add_head_commands(CLI::App& app);
void add_capture_commands(CLI::App& app);
void add_calibrate_commands(CLI::App& app);
void add_live_commands(CLI::App& app);
void add_shoot_commands(CLI::App& app);

}  // namespace rostro::app
