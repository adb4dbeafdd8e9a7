#include "hydrolux/scatter/mueller.hpp"

#include <stdexcept>

namespace hydrolux::scatter {

namespace {
MuellerElements sized(std::size_t n) {
  return {std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
}
}  // namespace

MuellerElements mueller_elements(std::span<const Complex> s1, std::span<const Complex> s2) {
  if (s1.size() != s2.size()) throw std::invalid_argument("mueller_elements: S1 and S2 differ in size");
  MuellerElements out = sized(s1.size());
  for (std::size_t i = 0; i < s1.size(); ++i) {
    const MuellerElement e = mueller_element(s1[i], s2[i]);
    out.s11[i] = e.s11, out.s12[i] = e.s12, out.s33[i] = e.s33, out.s34[i] = e.s34;
  }
  return out;
}

MuellerElements mueller_elements(const Intensities& averaged) {
  const std::size_t n = averaged.i1.size();
  if (averaged.i2.size() != n || averaged.s2_s1conj.size() != n)
    throw std::invalid_argument("mueller_elements: the averaged intensities differ in size");
  MuellerElements out = sized(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.s11[i] = 0.5 * (averaged.i2[i] + averaged.i1[i]);
    out.s12[i] = 0.5 * (averaged.i2[i] - averaged.i1[i]);
    out.s33[i] = averaged.s2_s1conj[i].real();
    out.s34[i] = averaged.s2_s1conj[i].imag();
  }
  return out;
}

}  // namespace hydrolux::scatter
