// The pictures of `run` and `associate --plots` (engine/report/): the PNG encoder against an
// independent bitwise CRC-32 and zlib's inflate, the raster's coverage against hand-computed
// pixels, dash lengths, tick values, the map's red only where a link is wrong, and the CLI's files.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>

#include "engine/report/association_map.hpp"
#include "engine/report/figure.hpp"
#include "engine/report/raster_canvas.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/cli_runner.hpp"

namespace trackassoc::report {
namespace {

uint32_t bitwise_crc32(const std::string& bytes) {  // the PNG specification's CRC, bit by bit
  uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xffffffffu;
}

uint32_t be32(const std::string& s, std::size_t at) {
  return (uint32_t(uint8_t(s[at])) << 24) | (uint32_t(uint8_t(s[at + 1])) << 16) |
         (uint32_t(uint8_t(s[at + 2])) << 8) | uint32_t(uint8_t(s[at + 3]));
}

TEST(Png, ChunksCarryTheirCrcAndTheRowsInflateToThePixels) {
  const std::vector<uint8_t> rgb{255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  const std::string png = encode_png(3, 2, rgb);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::vector<std::string> types;
  std::string idat;
  for (std::size_t at = 8; at < png.size();) {
    const uint32_t length = be32(png, at);
    const std::string body = png.substr(at + 4, 4 + length);
    EXPECT_EQ(be32(png, at + 8 + length), bitwise_crc32(body)) << body.substr(0, 4);
    types.push_back(body.substr(0, 4));
    if (types.back() == "IHDR") {
      EXPECT_EQ(be32(body, 4), 3u);
      EXPECT_EQ(be32(body, 8), 2u);
      EXPECT_EQ(body.substr(12, 5), std::string("\x08\x02\x00\x00\x00", 5));
    }
    if (types.back() == "IDAT") idat += body.substr(4);
    at += 12 + length;
  }
  EXPECT_EQ(types, (std::vector<std::string>{"IHDR", "IDAT", "IEND"}));
  std::vector<uint8_t> raw(2 * (1 + 9));
  uLongf size = raw.size();
  ASSERT_EQ(uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()), Z_OK);
  ASSERT_EQ(size, 20u);
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(raw[y * 10], 0) << "filter byte of row " << y;
    for (int i = 0; i < 9; ++i) EXPECT_EQ(raw[y * 10 + 1 + i], rgb[y * 9 + i]);
  }
  EXPECT_THROW(encode_png(3, 3, rgb), InputError);
}

TEST(Raster, CoverageOfRectanglesAndLinesAsWorkedOutByHand) {
  RasterCanvas c(12, 12);
  // Half of pixel (1, 1) covered in black: 255 + 0.5·(0 − 255) = 127.5, rounded to 128.
  c.fill_rect(1.0, 1.0, 0.5, 1.0, rgb(0x000000));
  EXPECT_EQ(c.pixel(1, 1).r, 128);
  EXPECT_EQ(c.pixel(2, 1).r, 255);
  // A 1 px line along the centres of row 6 covers it fully between its ends and leaves rows 5, 7.
  c.line(3.5, 6.5, 9.5, 6.5, {rgb(0x0000ff), 1.0});
  for (int x = 3; x <= 9; ++x) EXPECT_EQ(c.pixel(x, 6).b, 255) << x;
  EXPECT_EQ(c.pixel(5, 6).r, 0);
  EXPECT_EQ(c.pixel(5, 5).r, 255);
  EXPECT_EQ(c.pixel(5, 7).r, 255);
}

TEST(Dashes, OnPiecesAddUpToThePattern) {
  // 100 px with dashes of 10 on, 5 off: pieces start at 0, 15, ..., 90; the last one is 10 long.
  const auto pieces = dash_polyline({{0, 0}, {60, 0}, {60, 40}}, {10, 5});
  ASSERT_EQ(pieces.size(), 7u);
  double drawn = 0;
  for (const auto& p : pieces)
    for (std::size_t i = 1; i < p.size(); ++i) drawn += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  EXPECT_NEAR(drawn, 70.0, 1e-9);
  EXPECT_EQ(dash_polyline({{0, 0}, {5, 0}}, {}).size(), 1u);  // solid: the line itself
}

TEST(Ticks, RoundStepsCoverTheRange) {
  // (61 + 43) / 8 = 13 per tick, 1.3 × 10 rounds to a step of 10; (104) / 4 = 26 rounds to 20.
  EXPECT_EQ(nice_ticks(-43.0, 61.0, 8), (std::vector<double>{-40, -30, -20, -10, 0, 10, 20, 30, 40, 50, 60}));
  EXPECT_EQ(nice_ticks(-43.0, 61.0, 4), (std::vector<double>{-40, -20, 0, 20, 40, 60}));
  const std::vector<double> fifths = nice_ticks(0.0, 1.0, 5);
  ASSERT_EQ(fifths.size(), 6u);
  for (int k = 0; k <= 5; ++k) EXPECT_NEAR(fifths[k], 0.2 * k, 1e-12);
  EXPECT_EQ(sibling_picture("out/run.png", "-summary"), "out/run-summary.png");
  EXPECT_EQ(sibling_picture("out.d/run", "-summary"), "out.d/run-summary");
  EXPECT_EQ(picture_path("run.png", true), "run.svg");
  EXPECT_EQ(picture_format("a.svg", false), ImageFormat::kSvg);
  EXPECT_EQ(picture_format("a.png", false), ImageFormat::kPng);
}

// Two sensors, two targets 5 km apart, straight tracks; the tuples join either each target's two
// tracks (right) or crosswise (wrong).
TrackFile two_target_file() {
  TrackFile f;
  for (int32_t id : {0, 1}) f.sensors.push_back(Sensor{.id = id});
  TrackTable& t = f.tracks;
  for (int32_t s = 0; s < 2; ++s)
    for (int32_t target = 0; target < 2; ++target)
      for (int k = 0; k < 10; ++k) {
        t.sensor.push_back(s);
        t.track.push_back(target);
        t.t.push_back(k);
        t.truth.push_back(target);
        const double st[4] = {1000.0 * k, 5000.0 * target + 20.0 * s, 1000, 0};
        for (int d = 0; d < 4; ++d) t.state[d].push_back(st[d]);
        for (auto& c : t.cov) c.push_back(0.0);
      }
  return f;
}

int pure_red_pixels(const TrackFile& f, const std::vector<int32_t>& tuples) {
  AssociationRecord rec;
  rec.name = "test";
  rec.num_sensors = 2;
  rec.tuples = tuples;
  RasterCanvas canvas(kMapWidth, kMapHeight);
  draw_association_map(canvas, f, rec, "test");
  int red = 0;
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = 0; x < canvas.width() - 260; ++x) {  // the map, not its legend
      const Rgb p = canvas.pixel(x, y);
      red += p.r == 0xd6 && p.g == 0x27 && p.b == 0x28;
    }
  return red;
}

TEST(AssociationMap, RedOnlyWhereALinkIsWrong) {
  const TrackFile f = two_target_file();
  EXPECT_EQ(pure_red_pixels(f, {0, 0, 1, 1}), 0);
  EXPECT_GT(pure_red_pixels(f, {0, 1, 1, 0}), 50);  // two wrong links, each a 2.6 px line and a ring
}

class PicturesCli : public testing_support::CliFixture {};

TEST_F(PicturesCli, RunWritesTheMapAndTheSummaryAsPngOrSvg) {
  const auto r = run("run --solvers default,greedy --output " + path("r.h5") + " --plots " + path("r.png"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(path("r.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(slurp(path("r-summary.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const auto s = run("run --solvers default --svg --output " + path("s.h5") + " --plots " + path("s.png"));
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_EQ(slurp(path("s.svg")).substr(0, 4), "<svg");
  EXPECT_EQ(slurp(path("s-summary.svg")).substr(0, 4), "<svg");
  EXPECT_FALSE(std::filesystem::exists(path("s.png")));
  const auto a = run("associate -i " + path("r.h5") + " -o " + path("a.h5") + " --plots " + path("a.png"));
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_EQ(slurp(path("a.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

}  // namespace
}  // namespace trackassoc::report
