// The usage text of `aquaform` and of each of its commands (`aquaform help`, `COMMAND --help`).
#pragma once

#include <string>
#include <vector>

namespace aquaform::cli {

/// `aquaform help`: every command with its flags, and the render flags.
void print_usage();
/// `aquaform COMMAND ... --help`: that command's part of the usage; false when `argv` asks for
/// no help. (The flag is taken wherever it stands, so `run scene.json --help` helps too.)
bool print_command_help(const std::string& command, const std::vector<std::string>& argv);

}  // namespace aquaform::cli
