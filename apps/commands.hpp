#pragma once
// Each command group adds its subcommands to the program here. A subcommand's callback
// throws rostro::InputError for bad input; main() turns that into one line and exit 1.

#include <CLI/CLI.hpp>

namespace rostro::app {

void add_fap_commands(CLI::App& app);

}  // namespace rostro::app
