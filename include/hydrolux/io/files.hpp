#pragma once
// Writing output files safely: everything is written to a temporary file next to the target and
// renamed into place, so a failure (or a crash) never leaves a half-written or clobbered file.
#include <filesystem>
#include <functional>
#include <string_view>

namespace hydrolux::io {

// A temporary path in the same directory as `target`, keeping its extension (image writers pick
// the format from it): <dir>/.<stem>.tmp-<pid>-<n><ext>.
std::filesystem::path temporary_path_for(const std::filesystem::path& target);

// Calls write(tmp) and renames tmp onto target; removes tmp and rethrows if write throws.
// Creates the target's directory if needed. Throws IoError on rename failure.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

// Writes text to `target` atomically. Throws IoError.
void write_text_file(const std::filesystem::path& target, std::string_view text);

}  // namespace hydrolux::io
