// Rain detection (rain/detect.hpp) stage by stage on frames built here, each from the property the stage
// tests (Garg & Nayar, "Detection and Removal of Rain from Videos", CVPR 2004), and the scores counted by
// hand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/rain/detect.hpp"

namespace hydrolux::rain {
namespace {

GreyFrame flat(int w, int h, float level) {
  return GreyFrame{w, h, std::vector<float>(std::size_t(w) * std::size_t(h), level)};
}
float& at(GreyFrame& f, int x, int y) { return f.level[std::size_t(y) * std::size_t(f.width) + std::size_t(x)]; }
bool on(const Mask& m, int x, int y) { return m.on[std::size_t(y) * std::size_t(m.width) + std::size_t(x)] != 0; }

}  // namespace

// Garg & Nayar's candidate: brighter than the frame before and the frame after, each by at least c.
TEST(RainDetect, CandidatesAreBrighterThanBothNeighboursByC) {
  GreyFrame prev = flat(16, 16, 100), now = flat(16, 16, 100), next = flat(16, 16, 100);
  at(now, 5, 5) = 103;                         // 3 above both: a candidate (c = 3 reached)
  at(now, 6, 6) = 102.9f;                      // below c
  at(now, 7, 7) = 110, at(next, 7, 7) = 110;   // above the frame before only: something that stays
  at(now, 8, 8) = 90;                          // darker
  const Mask m = rain_candidates(prev, now, next, 3);
  EXPECT_TRUE(on(m, 5, 5));
  EXPECT_FALSE(on(m, 6, 6));
  EXPECT_FALSE(on(m, 7, 7));
  EXPECT_FALSE(on(m, 8, 8));
  EXPECT_EQ(m.count(), 1u);
}

// The photometric test: a drop that covers a pixel for tau of the exposure T changes it by
// dI = tau E_drop - (tau / T) I_bg, a line in the background I_bg of slope -beta = -tau / T. A streak drawn
// here with beta = 0.02 over a background ramp passes the bound 1.18 ms / 30 ms = 0.039; the same streak
// with beta = 0.2 (an object that covers the pixel for a fifth of the exposure: too slow for a drop) fails.
TEST(RainDetect, ThePhotometricTestBoundsTheSlopeOfTheChangeAgainstTheBackground) {
  DetectSettings s;
  EXPECT_NEAR(max_beta(s), 0.0393, 1e-4);  // Garg & Nayar's 0.039 at 30 ms
  for (const double beta : {0.02, 0.2}) {
    GreyFrame prev = flat(40, 40, 0), now = flat(40, 40, 0), next = flat(40, 40, 0);
    Mask cand{40, 40, std::vector<std::uint8_t>(1600, 0)};
    const double alpha = beta * 255 + 6;  // tau E_drop: the drop brighter than any background here
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) at(prev, x, y) = at(next, x, y) = at(now, x, y) = float(40 + 4 * x);
    for (int y = 5; y < 25; ++y) {  // a streak, one pixel wide, across the ramp diagonally
      const int x = 5 + y;
      const double bg = at(prev, x, y);
      at(now, x, y) = float(bg + alpha - beta * bg);
      cand.on[std::size_t(y) * 40 + std::size_t(x)] = 1;
    }
    const Mask kept = photometric_test(cand, prev, now, next, max_beta(s));
    EXPECT_EQ(kept.count(), beta < max_beta(s) ? 20u : 0u) << "beta " << beta;
  }
  // A streak over a background that varies by less than a grey level cannot test the slope: it is kept, even
  // where its changes would fit a slope of 0.5 (the ramp of 0.05 levels a pixel makes beta = 0.5 from noise).
  {
    GreyFrame p2 = flat(20, 20, 0), n2 = flat(20, 20, 0), c2 = flat(20, 20, 0);
    Mask cand2{20, 20, std::vector<std::uint8_t>(400, 0)};
    for (int y = 2; y < 12; ++y) {
      const float bg = 80 + 0.05f * float(y);
      at(p2, 4, y) = at(n2, 4, y) = bg;
      at(c2, 4, y) = bg + 70 - 0.5f * bg;
      cand2.on[std::size_t(y) * 20 + 4] = 1;
    }
    EXPECT_EQ(photometric_test(cand2, p2, c2, n2, max_beta(s)).count(), 10u);
    for (int y = 2; y < 12; ++y) {  // the same slope over a background spread over 9 grey levels: rejected
      const float bg = 80 + 1.0f * float(y);
      at(p2, 4, y) = at(n2, 4, y) = bg;
      at(c2, 4, y) = bg + 70 - 0.5f * bg;
    }
    EXPECT_EQ(photometric_test(cand2, p2, c2, n2, max_beta(s)).count(), 0u);
  }
  // A streak over a background that varies less than a grey level cannot test the slope: it is kept.
  GreyFrame prev = flat(20, 20, 80), now = flat(20, 20, 80), next = flat(20, 20, 80);
  Mask cand{20, 20, std::vector<std::uint8_t>(400, 0)};
  for (int y = 2; y < 12; ++y) at(now, 4, y) = 150, cand.on[std::size_t(y) * 20 + 4] = 1;
  EXPECT_EQ(photometric_test(cand, prev, now, next, max_beta(s)).count(), 10u);
}

// The correlation of streaks that fall in one direction is a needle along it; a pixel of a streak across
// that direction is dropped. 30 frames of vertical streaks, 7 pixels long at random places, and in frame
// 15 one horizontal streak besides.
TEST(RainDetect, TheCorrelationKeepsStreaksAlongTheRainsDirection) {
  const int w = 96, h = 96;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> px(8, w - 9);
  std::vector<Mask> masks(30, Mask{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 0)});
  for (auto& m : masks)
    for (int k = 0; k < 12; ++k) {
      const int x = px(rng), y = px(rng);
      for (int d = -3; d <= 3; ++d) m.on[std::size_t(y + d) * w + std::size_t(x)] = 1;
    }
  Mask& frame = masks[15];
  for (int y = 0; y < h; ++y)  // a clear row for the horizontal streak
    for (int x = 40; x < 60; ++x) frame.on[std::size_t(y) * w + std::size_t(x)] = y == 48 && x >= 46 && x <= 52;
  for (auto& m : masks)
    for (int y = 40; y < 57; ++y)
      for (int x = 38; x < 62; ++x)
        if (&m != &frame) m.on[std::size_t(y) * w + std::size_t(x)] = 0;
  DetectSettings s;
  const Needle across = correlation_needle(masks, 15, 49, 48, s);
  EXPECT_NEAR(across.direction_deg, 0, 1e-9);  // along the image's x axis
  EXPECT_NEAR(across.elongation, 1, 1e-9);     // a straight line's correlation lies on it
  const Mask kept = correlation_test(masks, 15, s);
  for (int x = 46; x <= 52; ++x) EXPECT_FALSE(on(kept, x, 48)) << x;
  std::size_t vertical = 0, vertical_kept = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (on(frame, x, y) && !(y == 48 && x >= 46 && x <= 52)) {
        ++vertical;
        vertical_kept += on(kept, x, y);
        if (vertical == 1) {
          const Needle n = correlation_needle(masks, 15, x, y, s);
          EXPECT_NEAR(n.direction_deg, 90, 20) << "a vertical streak's needle, frames of others around";
        }
      }
  ASSERT_GT(vertical, 50u);
  // A 4 x 5 blob, upright like the rain but hardly elongated ((l1 - l2) / (l1 + l2) = (24 - 15) / (24 + 15) =
  // 0.23 for the autocorrelation of a w x h rectangle, moments in the ratio w^2 - 1 : h^2 - 1): dropped by the
  // elongation bound alone, kept without it.
  std::vector<Mask> blob = masks;
  for (int y = 10; y < 15; ++y)
    for (int x = 44; x < 48; ++x) blob[15].on[std::size_t(y) * w + std::size_t(x)] = 1;
  for (int y = 4; y < 21; ++y)  // nothing else near it in any frame
    for (int x = 38; x < 54; ++x)
      for (auto& m : blob)
        if (&m != &blob[15] || y < 10 || y >= 15 || x < 44 || x >= 48) m.on[std::size_t(y) * w + std::size_t(x)] = 0;
  const Needle upright = correlation_needle(blob, 15, 45, 12, s);
  EXPECT_NEAR(upright.direction_deg, 90, 1e-9);
  EXPECT_NEAR(upright.elongation, 9.0 / 39.0, 1e-9);
  EXPECT_FALSE(on(correlation_test(blob, 15, s), 45, 12));
  DetectSettings any_shape = s;
  any_shape.min_elongation = 0;
  EXPECT_TRUE(on(correlation_test(blob, 15, any_shape), 45, 12));
  // Streaks that cross others in the window broaden their needle; most stay within the bounds.
  EXPECT_GT(double(vertical_kept), 0.9 * double(vertical));
}

// The median baseline: brighter than the median of the 5 frames around by c.
TEST(RainDetect, TheMedianResidual) {
  std::vector<GreyFrame> f(5, flat(8, 8, 50));
  at(f[2], 3, 3) = 54;
  at(f[1], 4, 4) = 60, at(f[2], 4, 4) = 60, at(f[3], 4, 4) = 60;  // three of five: the median itself
  const Mask m = median_residual(f, 2, 5, 3);
  EXPECT_TRUE(on(m, 3, 3));
  EXPECT_FALSE(on(m, 4, 4));
  // At the sequence's ends the window moves inside it: frame 0 against the median of frames 0-4.
  at(f[0], 1, 1) = 58;
  EXPECT_TRUE(on(median_residual(f, 0, 5, 3), 1, 1));
  at(f[4], 2, 2) = 58;
  EXPECT_TRUE(on(median_residual(f, 4, 5, 3), 2, 2));
  EXPECT_EQ(median_residual(f, 4, 5, 3).count(), 1u);
  DetectSettings s;
  s.method = DetectMethod::median;
  s.median_frames = 7;
  EXPECT_THROW(detect_rain(f, s), ParamError);  // more frames than the sequence has
}

TEST(RainDetect, RefusesTooFewFramesAndMixedSizes) {
  DetectSettings s;
  std::vector<GreyFrame> two(2, flat(4, 4, 0));
  EXPECT_THROW(detect_rain(two, s), Error);
  std::vector<GreyFrame> mixed{flat(4, 4, 0), flat(4, 4, 0), flat(5, 4, 0)};
  EXPECT_THROW(detect_rain(mixed, s), Error);
  s.window_px = 10;
  EXPECT_THROW(validate(s), ParamError);
}

// Scores by hand: 3 true rain pixels (alpha >= 0.05), of which 2 predicted; 1 faint (ignored, predicted);
// 4 clear, of which 1 predicted.
TEST(RainDetect, ScoresCountedByHand) {
  const std::vector<std::uint8_t> pred{1, 1, 0, 1, 1, 0, 0, 0};
  const std::vector<float> alpha{0.5f, 0.05f, 0.3f, 0.02f, 0.f, 0.f, 0.009f, 0.f};
  const Confusion c = score_mask(pred, alpha, EvalSettings{});
  EXPECT_EQ(c.true_positive, 2u);
  EXPECT_EQ(c.false_negative, 1u);
  EXPECT_EQ(c.ignored, 1u);
  EXPECT_EQ(c.false_positive, 1u);
  EXPECT_EQ(c.true_negative, 3u);
  EXPECT_DOUBLE_EQ(c.precision(), 2.0 / 3);
  EXPECT_DOUBLE_EQ(c.recall(), 2.0 / 3);
  EXPECT_DOUBLE_EQ(c.f1(), 2.0 / 3);
  EXPECT_DOUBLE_EQ(c.iou(), 0.5);
  EXPECT_TRUE(std::isnan(Confusion{}.precision()));
}

// A frame's grey levels: Rec. 601 luma of the sRGB-encoded values on 0-255, the scale of c (written out
// here with the sRGB curve's formula; the library interpolates it, within 0.01 grey levels).
TEST(RainDetect, GreyLevelsAreTheLumaOfTheSrgbCodes) {
  const auto srgb = [](double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055; };
  Image img(64, 1, 3);
  for (int i = 0; i < 64; ++i) {
    img.pixels[std::size_t(i) * 3] = float(std::pow(i / 63.0, 3));
    img.pixels[std::size_t(i) * 3 + 1] = float(0.0031308 * (i % 7) / 3.0);
    img.pixels[std::size_t(i) * 3 + 2] = float((i * 37 % 64) / 63.0);
  }
  const GreyFrame g = grey_levels(img);
  for (int i = 0; i < 64; ++i) {
    const float* p = &img.pixels[std::size_t(i) * 3];
    const double want = 255 * (0.299 * srgb(p[0]) + 0.587 * srgb(p[1]) + 0.114 * srgb(p[2]));
    EXPECT_NEAR(g.level[std::size_t(i)], want, 0.01) << i;
  }
}

// Garg & Nayar's removal: a masked pixel gets the mean of the frames before and after; a neighbour that is
// rain there itself gives way to the frame beyond it; with no usable frame on either side the pixel stays.
TEST(RainRemove, FromTheNeighbouringFrames) {
  std::vector<Image> f;
  for (int t = 0; t < 5; ++t) {
    Image im(4, 1, 3);
    for (std::size_t k = 0; k < im.pixels.size(); ++k) im.pixels[k] = float(10 * t + int(k));
    f.push_back(im);
  }
  std::vector<Mask> m(5, Mask{4, 1, std::vector<std::uint8_t>(4, 0)});
  m[2].on = {1, 1, 0, 1};
  m[1].on = {0, 1, 0, 1};  // pixels 1 and 3 are rain in frame 1 too
  m[0].on = {0, 0, 0, 1};  // and pixel 3 in frame 0: no usable frame before frame 2 there
  m[3].on = {0, 0, 0, 1};
  m[4].on = {0, 0, 0, 1};  // nor after
  const Image out = remove_from_neighbours(f, m, 2);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(out.pixels[0 * 3 + c], 0.5f * (10 + 30) + float(c));      // frames 1 and 3
    EXPECT_FLOAT_EQ(out.pixels[1 * 3 + c], 0.5f * (0 + 30) + float(3 + c));   // frames 0 and 3
    EXPECT_FLOAT_EQ(out.pixels[2 * 3 + c], f[2].pixels[2 * 3 + c]);           // not masked
    EXPECT_FLOAT_EQ(out.pixels[3 * 3 + c], f[2].pixels[3 * 3 + c]);           // nothing usable: kept
  }
}

TEST(RainRemove, TemporalMedianAndTheLayerInverted) {
  std::vector<Image> f;
  for (const float v : {0.1f, 0.9f, 0.3f, 0.2f, 0.5f}) {
    Image im(1, 1, 3);
    im.pixels = {v, v, v};
    f.push_back(im);
  }
  EXPECT_FLOAT_EQ(temporal_median(f, 2, 5).pixels[0], 0.3f);
  EXPECT_FLOAT_EQ(temporal_median(f, 0, 3).pixels[0], 0.3f);  // the window moved inside: frames 0-2
  // rainy = clear (1 - alpha) + layer, written out here, inverted.
  Image clear(2, 1, 3), layer(2, 1, 4), rainy(2, 1, 3);
  clear.pixels = {0.2f, 0.4f, 0.6f, 0.7f, 0.1f, 0.3f};
  layer.pixels = {0.05f, 0.1f, 0.15f, 0.25f, 0.5f, 0.5f, 0.5f, 1.0f};
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t c = 0; c < 3; ++c)
      rainy.pixels[i * 3 + c] = clear.pixels[i * 3 + c] * (1 - layer.pixels[i * 4 + 3]) + layer.pixels[i * 4 + c];
  const Image back = invert_rain_layer(rainy, layer);
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(back.pixels[c], clear.pixels[c], 1e-6);
    EXPECT_FLOAT_EQ(back.pixels[3 + c], rainy.pixels[3 + c]);  // alpha 1: nothing of the scene left, kept
  }
}

// PSNR on the sRGB codes: a value 255 codes off in each channel of the one rain pixel is 0 dB; equal frames
// outside, +inf; the faint streak's pixel counted in neither.
TEST(RainRemove, PsnrInAndOutOfTheRainByHand) {
  Image clean(3, 1, 3), derained(3, 1, 3);
  clean.pixels = {0, 0, 0, 0.5f, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f};
  derained.pixels = {1, 1, 1, 0.5f, 0.5f, 0.5f, 0.9f, 0.9f, 0.9f};
  const std::vector<float> alpha{0.5f, 0.f, 0.02f};
  const RemovalError e = removal_error(derained, clean, alpha, EvalSettings{});
  EXPECT_EQ(e.values_in, 3u);
  EXPECT_EQ(e.values_out, 3u);
  EXPECT_NEAR(e.psnr_in(), 0.0, 1e-9);
  EXPECT_TRUE(std::isinf(e.psnr_out()));
}

// Frames of different channel counts are refused, not read at the wrong stride; NaN is refused by name.
TEST(RainRemove, RefusesUnlikeFramesAndNonFiniteValues) {
  std::vector<Image> f{Image(4, 4, 3), Image(4, 4, 1), Image(4, 4, 3)};
  EXPECT_THROW(temporal_median(f, 1, 3), Error);
  std::vector<Mask> m(3, Mask{4, 4, std::vector<std::uint8_t>(16, 1)});
  EXPECT_THROW(remove_from_neighbours(f, m, 1), Error);
  Image bad(4, 4, 3);
  bad.pixels[5 * 3 + 1] = std::nanf("");
  try {
    check_finite(bad, "frames[2]");
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "frames[2]: a non-finite value (nan) at pixel (1, 1), channel 1; rain detection and removal "
                           "take finite light");
  }
}

}  // namespace hydrolux::rain
