#pragma once
// The files under data/ compiled into the library (see cmake/EmbedData.cmake), so physical tables
// travel with the binary and no data directory is needed at run time.
#include <string_view>
#include <vector>

namespace hydrolux {

namespace detail {
struct EmbeddedFile {
  std::string_view path;  // relative to data/, e.g. "media/gold_johnson_christy_1972.csv"
  std::string_view text;
};
const std::vector<EmbeddedFile>& embedded_files();
}  // namespace detail

// The text of data/<path>; throws IoError if no such file was embedded.
std::string_view embedded_file(std::string_view path);

}  // namespace hydrolux
