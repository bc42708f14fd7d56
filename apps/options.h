// Validators for the command line's options: each says what it expects and what it got, e.g.
// `--spp: expected a positive integer, got "abc"` (CLI11 puts the option's name in front).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace ml {

CLI::Validator positive_integer();      // 1, 2, ... up to INT_MAX
CLI::Validator non_negative_integer();  // 0, 1, ... up to INT_MAX
CLI::Validator seed_value();            // 0 ... 2^63 - 1
CLI::Validator positive_seconds();      // a finite number > 0
CLI::Validator share_of_time();         // a number in (0, 0.5]
CLI::Validator image_size();            // WxH, both positive
CLI::Validator one_of(const std::vector<std::string>& names, const std::string& what);
CLI::Validator setting();       // NAME.KEY=VALUE
CLI::Validator output_image();  // .exr, .png or .pfm in a folder that exists
CLI::Validator file_in_existing_folder();
CLI::Validator non_negative_seconds();  // 0 or more seconds

// Every message the command line prints starts with this.
inline constexpr const char* kMessagePrefix = "manylight: ";
// The exit code of a render stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report it).
inline constexpr int kInterruptedExit = 130;

}  // namespace ml
