#pragma once
// Checks of the options that size work (frame rates, durations), so that a typo never
// turns into hours of work, gigabytes of memory or a file rostro itself rejects.

#include <initializer_list>
#include <string>

#include "facecore/fap_io.hpp"

namespace rostro::app {

// Throws InputError unless `fps` is finite, > 0 and <= 1000.
void check_fps(double fps, const std::string& option);
// Throws InputError unless `seconds` is finite, > 0 and <= `max` (default: a day).
void check_seconds(double seconds, const std::string& option, double max = 86400.0);

// An output file and the option that names it, for check_not_an_input().
struct NamedOutput {
  const std::string& path;  // empty: not asked for, skipped
  const char* option;
};

// Throws InputError when one of `outputs` names the same file as one of `inputs` (empty
// names are skipped): a command never writes over what it reads.
void check_not_an_input(std::initializer_list<NamedOutput> outputs,
                        std::initializer_list<std::string> inputs);

// After `sink` finished writing `path`: a warning line on stderr when Xface (2004) cannot
// read it (a .fap with a fractional frame rate or the high-level FAP 1/2).
void warn_if_xface_cannot_read(const FapSink& sink, const std::string& path);

}  // namespace rostro::app
