// Codecs declared once (engine/distributed/codec.hpp): every declared field travels, a buffer of
// the wrong length is refused naming the codec, and the codecs the engine declares round-trip
// the values they carry (the S-D link matrices, dense and sparse, through their gated entries).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/distributed/codec.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/sparse_sd_components.hpp"

namespace trackassoc {
namespace {

enum class Colour : int16_t { kRed = 3, kBlue = -9 };

struct Inner {
  int32_t a = 0;
  std::string b;
};

// One field of every kind the codec knows.
struct Everything {
  int32_t i = 0;
  double d = 0.0;
  bool flag = false;
  Colour colour = Colour::kRed;
  std::string text;
  std::vector<float> floats;
  std::vector<std::vector<int32_t>> nested;
  std::array<double, 3> triple{};
  std::array<std::vector<double>, 2> pair_of_vectors;
  Inner inner;
  std::vector<Inner> inners;
  uint64_t last = 0;
};

constexpr auto wire_codec(std::type_identity<Inner>) {
  return distributed::codec<Inner>("inner", &Inner::a, &Inner::b);
}
constexpr auto wire_codec(std::type_identity<Everything>) {
  return distributed::codec<Everything>(
      "everything", &Everything::i, &Everything::d, &Everything::flag, &Everything::colour, &Everything::text,
      &Everything::floats, &Everything::nested, &Everything::triple, &Everything::pair_of_vectors,
      &Everything::inner, &Everything::inners, &Everything::last);
}

Everything sample() {
  Everything x;
  x.i = -123456;
  x.d = -0.0;
  x.flag = true;
  x.colour = Colour::kBlue;
  x.text = std::string("seed") + '\0' + "004 row";  // 12 characters: an embedded NUL travels too
  x.floats = {1.5f, std::numeric_limits<float>::infinity(), -2.25f};
  x.nested = {{1, 2}, {}, {3}};
  x.triple = {1e300, -1e-300, 7.0};
  x.pair_of_vectors = {std::vector<double>{0.25}, std::vector<double>{}};
  x.inner = {42, "inner"};
  x.inners = {{1, "a"}, {2, ""}};
  x.last = 0xfedcba9876543210ull;
  return x;
}

const auto& kEverything = distributed::codec_of<Everything>();

TEST(Codec, EveryDeclaredFieldRoundTrips) {
  static_assert(
      distributed::Codec<Everything, int32_t, double, bool, Colour, std::string, std::vector<float>,
                         std::vector<std::vector<int32_t>>, std::array<double, 3>,
                         std::array<std::vector<double>, 2>, Inner, std::vector<Inner>, uint64_t>::fields() ==
      12);
  const Everything x = sample();
  const Everything y = kEverything.from_bytes(kEverything.to_bytes(x));
  EXPECT_EQ(y.i, -123456);
  EXPECT_TRUE(std::signbit(y.d));  // -0.0, bit for bit
  EXPECT_TRUE(y.flag);
  EXPECT_EQ(y.colour, Colour::kBlue);
  EXPECT_EQ(y.text.size(), 12u);
  EXPECT_EQ(y.text, x.text);
  EXPECT_EQ(y.text[4], '\0');
  EXPECT_EQ(y.text.substr(5), "004 row");
  EXPECT_EQ(y.floats, x.floats);
  EXPECT_EQ(y.nested, (std::vector<std::vector<int32_t>>{{1, 2}, {}, {3}}));
  EXPECT_EQ(y.triple, x.triple);
  EXPECT_EQ(y.pair_of_vectors[0], std::vector<double>{0.25});
  EXPECT_TRUE(y.pair_of_vectors[1].empty());
  EXPECT_EQ(y.inner.a, 42);
  EXPECT_EQ(y.inner.b, "inner");
  ASSERT_EQ(y.inners.size(), 2u);
  EXPECT_EQ(y.inners[0].b, "a");
  EXPECT_EQ(y.inners[1].a, 2);
  EXPECT_EQ(y.last, 0xfedcba9876543210ull);
}

TEST(Codec, TheBytesAreTheFieldsInDeclarationOrder) {
  // Worked out by hand: int32 (4) + double (8) + bool (1) + int16 enum (2) + string (8 + 12) + 3
  // floats (8 + 12) + nested (8 + (8 + 8) + 8 + (8 + 4)) + array (24) + array of vectors
  // (8 + 8 + 8) + inner (4 + 8 + 5) + inners (8 + (4 + 8 + 1) + (4 + 8)) + uint64 (8) = 205.
  const distributed::Bytes b = kEverything.to_bytes(sample());
  EXPECT_EQ(b.size(), 205u);
  int32_t first = 0;
  std::memcpy(&first, b.data(), 4);
  EXPECT_EQ(first, -123456);
  uint64_t last = 0;
  std::memcpy(&last, b.data() + b.size() - 8, 8);
  EXPECT_EQ(last, 0xfedcba9876543210ull);
  EXPECT_EQ(b[12], 1);  // the bool, one byte after the int and the double
}

TEST(Codec, AWrongLengthIsRefusedNamingTheCodec) {
  const distributed::Bytes b = kEverything.to_bytes(sample());
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, b.size() / 2, b.size() - 1}) {
    const distributed::Bytes shorter(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(cut));
    try {
      kEverything.from_bytes(shorter);
      FAIL() << "a buffer of " << cut << " bytes was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("'everything' (" + std::to_string(cut) + " bytes)"),
                std::string::npos)
          << e.what();
    }
  }
  distributed::Bytes longer = b;
  longer.push_back(0);
  try {
    kEverything.from_bytes(longer);
    FAIL() << "a longer buffer was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(
        e.what(),
        "distributed message 'everything' (206 bytes) is longer than its declared fields: 1 bytes left "
        "over (a bug)");
  }
  distributed::Bytes bad_bool = b;
  bad_bool[12] = 2;
  EXPECT_THROW(kEverything.from_bytes(bad_bool), std::runtime_error);
  // A corrupt count is refused before any allocation of its size.
  distributed::Bytes huge_count = b;
  const uint64_t n = uint64_t{1} << 60;
  std::memcpy(huge_count.data() + 15, &n, 8);  // the string's length
  EXPECT_THROW(kEverything.from_bytes(huge_count), std::runtime_error);
}

TEST(Codec, TheEngineCodecsRoundTripWhatTheyCarry) {
  SDComponentView v;
  v.S = 3;
  v.tracks = {{0, 1}, {0}, {0, 1, 2}};
  v.node = {{4, 9}, {2}, {1, 3, 5}};
  v.first = {{0, 2}, {1}, {0, -1, 3}};
  v.last = {{5, 8}, {9}, {4, -1, 7}};
  v.bytes_held = 1e9;  // the holder's own: stays behind
  v.link.resize(9);
  v.link[0 * 3 + 1] = SDLinkMatrix::from_entries(2, 1, {{1, 0, 2.5}});
  v.link[0 * 3 + 2] = SDLinkMatrix::from_entries(2, 3, {{0, 2, -1.0}, {1, 0, 0.5}});
  // A matrix over kDenseEntries is stored sparse (CSR); it travels and comes back sparse.
  v.link[1 * 3 + 2] = SDLinkMatrix::from_entries(1, 70000, {{0, 69999, 3.0}, {0, 5, 4.0}});
  ASSERT_TRUE(v.link[5].sparse);
  const SDComponentView w = distributed::codec_of<SDComponentView>().from_bytes(
      distributed::codec_of<SDComponentView>().to_bytes(v));
  EXPECT_EQ(w.S, 3);
  EXPECT_EQ(w.tracks, v.tracks);
  EXPECT_EQ(w.node, v.node);
  EXPECT_EQ(w.first, v.first);
  EXPECT_EQ(w.last, v.last);
  EXPECT_EQ(w.bytes_held, 0.0);
  EXPECT_EQ(w.link_cost(0, 1, 1, 0), 2.5);
  EXPECT_EQ(w.link_cost(2, 2, 0, 0), -1.0);
  EXPECT_EQ(w.link_cost(0, 1, 2, 0), 0.5);
  EXPECT_TRUE(std::isnan(w.link_cost(0, 0, 2, 0)));
  EXPECT_TRUE(w.link[5].sparse);
  EXPECT_EQ(w.link[5].at(0, 69999), 3.0);
  EXPECT_EQ(w.link[5].at(0, 5), 4.0);
  EXPECT_TRUE(std::isnan(w.link[5].at(0, 6)));
  // Gated entries outside their matrix are refused.
  SDLinkMatrix::Gated g{2, 2, {4}, {1.0}};
  EXPECT_THROW(SDLinkMatrix::from_gated(g), std::runtime_error);

  SparseComponentSolution s;
  s.tuples = {{0, 1, 2}, {2, 0, 1}};
  s.summary.termination = Termination::kGapTolerance;
  s.summary.feasible = true;
  s.summary.objective = -12.5;
  s.summary.iterations = 77;
  s.summary.message = "stopped at the gap";
  const auto& sc = distributed::codec_of<SparseComponentSolution>();
  const SparseComponentSolution t = sc.from_bytes(sc.to_bytes(s));
  EXPECT_EQ(t.tuples, s.tuples);
  EXPECT_EQ(t.summary.termination, Termination::kGapTolerance);
  EXPECT_TRUE(t.summary.feasible);
  EXPECT_EQ(t.summary.objective, -12.5);
  EXPECT_TRUE(std::isnan(t.summary.lower_bound));
  EXPECT_EQ(t.summary.iterations, 77);
  EXPECT_EQ(t.summary.message, "stopped at the gap");
}

}  // namespace
}  // namespace trackassoc
