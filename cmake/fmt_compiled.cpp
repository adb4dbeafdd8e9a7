// The compiled part of {fmt} 9 (libfmt-dev), built here as a static library: Debian ships it only as
// libfmt.so, which would cost every start of the CLI a library load and bring the shared libstdc++
// back into an executable that carries its own (BENCHMARKS.md, "CLI start-up"). Header-only use
// (FMT_HEADER_ONLY) would instead compile fmt's implementation into every file that formats: four
// times the compile time of each. What this file holds is what the package's headers declare and
// leave to the library: the non-template functions of fmt/format-inl.h (defined out of line here,
// FMT_HEADER_ONLY being unset) and the explicit instantiations the headers declare `extern`.
// {fmt}: Copyright (c) 2012 - present, Victor Zverovich; MIT licence (/usr/share/doc/libfmt-dev/copyright).
#include <fmt/format-inl.h>

FMT_BEGIN_NAMESPACE
namespace detail {

template FMT_API auto dragonbox::to_decimal(float x) noexcept -> dragonbox::decimal_fp<float>;
template FMT_API auto dragonbox::to_decimal(double x) noexcept -> dragonbox::decimal_fp<double>;

#ifndef FMT_STATIC_THOUSANDS_SEPARATOR
template FMT_API locale_ref::locale_ref(const std::locale& loc);
template FMT_API auto locale_ref::get<std::locale>() const -> std::locale;
#endif

template FMT_API auto thousands_sep_impl(locale_ref) -> thousands_sep_result<char>;
template FMT_API auto decimal_point_impl(locale_ref) -> char;
template FMT_API void buffer<char>::append(const char*, const char*);
template FMT_API void vformat_to(buffer<char>&, string_view, basic_format_args<FMT_BUFFER_CONTEXT(char)>,
                                 locale_ref);

template FMT_API auto thousands_sep_impl(locale_ref) -> thousands_sep_result<wchar_t>;
template FMT_API auto decimal_point_impl(locale_ref) -> wchar_t;
template FMT_API void buffer<wchar_t>::append(const wchar_t*, const wchar_t*);

}  // namespace detail
FMT_END_NAMESPACE
