#pragma once
// Checks of the options that size work (frame rates, durations), so that a typo never
// turns into hours of work, gigabytes of memory or a file rostro itself rejects.

#include <string>

namespace rostro::app {

// Throws InputError unless `fps` is finite, > 0 and <= 1000.
void check_fps(double fps, const std::string& option);
// Throws InputError unless `seconds` is finite, > 0 and <= `max` (default: a day).
void check_seconds(double seconds, const std::string& option, double max = 86400.0);

}  // namespace rostro::app
