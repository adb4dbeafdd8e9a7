#pragma once
// Errors the library throws. Nothing in the library prints or exits: the CLI turns these into one
// line on stderr and exit code 2.
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace hydrolux {

// Base of every error hydrolux throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A door's spelling of a parameter or quantity: "--near-m" for "near_m" (the CLI's and the batch
// jobs' flags), the name itself for Python's keywords.
using Spelling = std::function<std::string(std::string_view quantity)>;

// `text` with each quantity it names between braces ("beyond {near_m}") spelled by `spell`, or by its
// name where `spell` is empty: how a message the library words for every door names the parameters.
// A name may be followed by '=' and a word ("{mode=}": with its value; "{mode=half-dome}": with that
// value, as ParamUse's reasons say them), passed to `spell` as it is.
std::string spell_quantities(std::string_view text, const Spelling& spell);
// `text` (a user's, or another error's message) to stand in such a text as it is: its braces doubled.
std::string escape_braces(std::string_view text);

// An error about parameters that go together, or one whose text a job reads ("{size_distribution}
// marshall-palmer:5 sets its own radii; omit {radius_um}"): the text names each parameter between
// braces, what() by the library's names and said() by a door's, so that no door rewrites it.
class ParamError : public Error {
 public:
  explicit ParamError(std::string text);
  std::string said(const Spelling& spell) const { return spell_quantities(text_, spell); }

 private:
  std::string text_;
};

// A number outside the domain where a model is valid: a wavelength outside a medium's table, an
// angle outside [0, 90] degrees, a NaN. Carries the quantity's name (snake_case with its unit, e.g.
// "wavelength_nm") so a caller can name its own flag or field for it.
//
// A range that follows from other quantities names them between braces in its context ("beyond
// {near_m}", "at most one frame interval, 1 / {fps}"): data a door spells its own way (said()), so
// that no door rewrites the text. what() spells them by the library's names ("beyond near_m").
class DomainError : public Error {
 public:
  DomainError(std::string quantity, double value, double lo, double hi, std::string context = {});
  // The same with the message given whole (a declared parameter's, which states its unit:
  // core/params.hpp); `unit` is the range's ("mm/h"), else the quantity's suffix says it.
  static DomainError with_message(std::string message, std::string quantity, double value, double lo, double hi,
                                  std::string unit = {});
  const std::string& quantity() const noexcept { return quantity_; }
  double value() const noexcept { return value_; }
  double lo() const noexcept { return lo_; }
  double hi() const noexcept { return hi_; }
  // What the range belongs to, e.g. "water (IAPWS R9-97)", or how it follows from another quantity
  // ("beyond {near_m}", "at most ...", "at least ..."), with its quantities between braces; may be empty.
  const std::string& context() const noexcept { return context_; }
  // "outside the valid range [lo, hi] unit (context)", without the quantity: for callers that name it
  // themselves; the context's quantities spelled by `spell` (none: the library's names).
  std::string range_text(const Spelling& spell = {}) const;
  // The whole message in a door's words: "--far-m 5 is outside the valid range [5.005, 10000] m (beyond
  // --near-m)", each quantity, the refused one and those its range follows from, spelled by `spell`.
  std::string said(const Spelling& spell) const;

 private:
  struct Whole {};
  DomainError(Whole, std::string message, std::string quantity, double value, double lo, double hi, std::string unit);
  std::string quantity_;
  double value_, lo_, hi_;
  std::string context_, unit_;
};

// A name that is not one of a known set (a medium, a theory). The message lists the valid names.
class UnknownNameError : public Error {
 public:
  using Error::Error;
};

// A file the caller named that cannot be used: missing, not a regular file, unreadable, malformed or
// too large to read; an output whose folder does not exist or is not writable, or that is the same
// file as an input. Found before any output is replaced; the CLI exits 2.
class IoError : public Error {
 public:
  using Error::Error;
};

// The operating system failed an operation that should have worked: a full disk, a quota, a
// file-size limit, an I/O error, a rename refused. The message names the path and the OS error;
// no output was replaced and no temporary file is left. The CLI exits 1.
class IoFailure : public Error {
 public:
  using Error::Error;
};

// A message made safe for one terminal line: control characters (a newline in a file name, an
// escape sequence in a value) and bytes that are not valid UTF-8 become visible escapes ("\n",
// "\x1b"); printable ASCII and valid UTF-8 pass unchanged. Error messages quote what the user
// gave, so the CLI prints every message through this.
std::string printable(std::string_view text);

// Throws DomainError unless lo <= value <= hi (NaN always throws).
void require_in_range(const char* quantity, double value, double lo, double hi,
                      const std::string& context = {});
// The same with a literal context: nothing is built unless the value is out of range (the checks
// sit on hot paths such as one Mie solution per size of a distribution).
inline void require_in_range(const char* quantity, double value, double lo, double hi,
                             const char* context) {
  if (!(value >= lo && value <= hi)) throw DomainError(quantity, value, lo, hi, context);
}

}  // namespace hydrolux
