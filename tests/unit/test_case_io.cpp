// Case files: exact numbers, every kind of malformed input named by file, line and field,
// atomic writes.
#include "cullproof/case_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

using namespace cullproof;
namespace fs = std::filesystem;

namespace {

const char* kPlanes =
    R"("frustum": {"planes": [[1,0,-1,0],[-1,0,-1,0],[0,1,-1,0],[0,-1,-1,0],[0,0,-3,-3],[0,0,1,3]]})";

std::string with_volume(const std::string& volume, const std::string& more = "") {
  return std::string("{\"id\": \"t\", ") + kPlanes + ", \"volume\": " + volume + more + "}";
}

// The message of the CaseError thrown by parsing `text`, or "" when it parses.
std::string error_of(const std::string& text, int first_line = 1) {
  try {
    parse_case(text, "cases.jsonl", first_line);
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

std::uint32_t bits(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("cullproof-test-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(CaseRead, EveryVolumeKindAndPlanes) {
  const Case c = parse_case(with_volume(R"({"obb": {"center": [1,2,3], "axes": [[1,0,0],[0,1,0],[0,0,1]], "half": [0.5, 0.25, 2]}})",
                                        R"(, "truth": "intersecting", "note": "hand-made")"));
  EXPECT_EQ(c.id, "t");
  ASSERT_TRUE(std::holds_alternative<Obb>(c.volume));
  EXPECT_EQ(std::get<Obb>(c.volume).half, glm::vec3(0.5f, 0.25f, 2.0f));
  EXPECT_EQ(c.frustum.planes[kNear].n.z, -3.0f);
  EXPECT_FALSE(c.frustum.matrix.has_value());
  EXPECT_EQ(c.truth, Visibility::intersecting);
  EXPECT_EQ(c.note, "hand-made");
  EXPECT_TRUE(std::holds_alternative<Point>(parse_case(with_volume("{\"point\": [0, 0, -2]}")).volume));
  EXPECT_TRUE(std::holds_alternative<Sphere>(
      parse_case(with_volume(R"({"sphere": {"center": [0,0,-2], "radius": 0}})")).volume));
  EXPECT_TRUE(std::holds_alternative<Aabb>(
      parse_case(with_volume(R"({"aabb": {"min": [0,0,-2], "max": [0,0,-2]}})")).volume));
}

TEST(CaseRead, MatrixFrustumIsExtractedInFloat) {
  const Case c = parse_case(R"({"id": "m", "frustum": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,-2,-1, 0,0,-3,0],
      "depth": "negative_one_to_one"}, "volume": {"point": [0,0,-2]}})");
  ASSERT_TRUE(c.frustum.matrix.has_value());
  EXPECT_FALSE(c.frustum.depth.reversed_z);  // absent means false
  EXPECT_EQ(c.frustum.planes[kFar].n, glm::vec3(0, 0, 1));
  EXPECT_EQ(c.frustum.planes[kFar].d, 3.0f);
}

TEST(CaseRead, HexFloatStringsAreExact) {
  const Case c = parse_case(with_volume(R"({"point": ["0x1.8p+3", "-0x1p-149", "0X1.FFFFFEp127"]})"));
  const Point p = std::get<Point>(c.volume);
  EXPECT_EQ(p.x, 12.0f);
  EXPECT_EQ(p.y, -std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(p.z, std::numeric_limits<float>::max());
}

// 1 + 2^-24 + 2^-60: just above the midpoint between 1 and the next float. Rounded through
// double it lands exactly on the midpoint and then ties to even (1.0f); rounded once from the
// text, as CONVENTIONS asks, it is the next float.
TEST(CaseRead, DecimalsRoundOnceToFloatNotThroughDouble) {
  EXPECT_EQ(parse_case_float("1.000000059604644776258", false), std::nextafter(1.0f, 2.0f));
  EXPECT_EQ(float(double(1.000000059604644776258)), 1.0f);  // what double rounding would give
}

TEST(CaseRead, UnderflowRoundsToZeroOverflowIsRejected) {
  EXPECT_EQ(parse_case_float("1e-60", false), 0.0f);
  EXPECT_THROW(parse_case_float("1e39", false), std::invalid_argument);
  EXPECT_THROW(parse_case_float("0x1p+128", true), std::invalid_argument);
  EXPECT_THROW(parse_case_float("inf", true), std::invalid_argument);
  EXPECT_THROW(parse_case_float("nan", true), std::invalid_argument);
  EXPECT_THROW(parse_case_float("1.5", true), std::invalid_argument);  // a string must be hex
}

TEST(CaseRead, UnknownTopLevelFieldsAreKept) {
  const Case c = parse_case(with_volume("{\"point\": [0,0,-2]}", R"(, "verdicts": {"pn-vertex": "inside"}, "seed": 7)"));
  EXPECT_EQ(c.extra["seed"], 7);
  EXPECT_EQ(c.extra["verdicts"]["pn-vertex"], "inside");
  const std::string out = format_case(c);
  EXPECT_NE(out.find("\"seed\": 7"), std::string::npos) << out;
}

// ---- malformed input: one test per kind, each naming file, line and field ----

TEST(CaseErrors, MissingField) {
  EXPECT_EQ(error_of(R"({"id": "x", "volume": {"point": [0,0,0]}})"), "cases.jsonl:1: field 'frustum': missing field");
  EXPECT_NE(error_of(with_volume(R"({"obb": {"center": [0,0,0], "half": [1,1,1]}})")).find("field 'volume.obb.axes': missing field"),
            std::string::npos);
}

TEST(CaseErrors, WrongArity) {
  EXPECT_NE(error_of(with_volume(R"({"aabb": {"min": [0,0], "max": [1,1,1]}})")).find("field 'volume.aabb.min': must have 3 elements, has 2"),
            std::string::npos);
  const std::string e = error_of(R"({"id": "x", "frustum": {"planes": [[1,0,0,0]]}, "volume": {"point": [0,0,0]}})");
  EXPECT_NE(e.find("field 'frustum.planes': must be an array of 6 planes"), std::string::npos) << e;
  EXPECT_NE(error_of(R"({"id": "x", "frustum": {"matrix": [1,2,3], "depth": "zero_to_one"}, "volume": {"point": [0,0,0]}})")
                .find("field 'frustum.matrix': must have 16 elements, has 3"),
            std::string::npos);
}

TEST(CaseErrors, NaNAndInfinity) {
  // JSON has no NaN token: the parser reports it with its line.
  EXPECT_NE(error_of(with_volume("{\"point\": [NaN, 0, 0]}")).find("cases.jsonl:1: invalid JSON"), std::string::npos);
  EXPECT_NE(error_of(with_volume(R"({"point": [0, "nan", 0]})")).find("field 'volume.point[1]': string \"nan\" is not a C99 hexadecimal float"),
            std::string::npos);
  EXPECT_NE(error_of(with_volume(R"({"point": [0, 0, 1e40]})")).find("field 'volume.point[2]': \"1e40\" overflows float"),
            std::string::npos);
}

TEST(CaseErrors, MinGreaterThanMax) {
  EXPECT_NE(error_of(with_volume(R"({"aabb": {"min": [0,2,0], "max": [1,1,1]}})")).find("field 'volume.aabb.min[1]': min > max (2 > 1)"),
            std::string::npos);
}

TEST(CaseErrors, NegativeRadiusAndHalfExtent) {
  EXPECT_NE(error_of(with_volume(R"({"sphere": {"center": [0,0,0], "radius": -1}})")).find("field 'volume.sphere.radius': is negative (-1)"),
            std::string::npos);
  EXPECT_NE(error_of(with_volume(R"({"obb": {"center": [0,0,0], "axes": [[1,0,0],[0,1,0],[0,0,1]], "half": [1,-0.5,1]}})"))
                .find("field 'volume.obb.half[1]': is negative (-0.5)"),
            std::string::npos);
}

TEST(CaseErrors, ZeroAxis) {
  EXPECT_NE(error_of(with_volume(R"({"obb": {"center": [0,0,0], "axes": [[1,0,0],[0,0,0],[0,0,1]], "half": [1,1,1]}})"))
                .find("field 'volume.obb.axes[1]': is a zero-length axis"),
            std::string::npos);
}

TEST(CaseErrors, VolumeKindsAndFrustumForms) {
  EXPECT_NE(error_of(with_volume(R"({"cone": [0,0,0]})")).find("unknown volume kind \"cone\""), std::string::npos);
  EXPECT_NE(error_of(with_volume(R"({"point": [0,0,0], "sphere": {"center": [0,0,0], "radius": 1}})")).find("exactly one of"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"id": "x", "frustum": {}, "volume": {"point": [0,0,0]}})").find("exactly one of \"planes\" and \"matrix\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"id": "x", "frustum": {"matrix": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1], "depth": "minus_one"}, "volume": {"point": [0,0,0]}})")
                .find("field 'frustum.depth': must be \"negative_one_to_one\" or \"zero_to_one\""),
            std::string::npos);
  EXPECT_NE(error_of(with_volume("{\"point\": [0,0,0]}", R"(, "truth": "visible")")).find("field 'truth': unknown visibility"),
            std::string::npos);
}

TEST(CaseErrors, DuplicateFieldAndWrongTypes) {
  EXPECT_NE(error_of(R"({"id": "a", "id": "b"})").find("field 'id': duplicate field"), std::string::npos);
  EXPECT_NE(error_of(with_volume(R"({"point": [0, true, 0]})")).find("field 'volume.point[1]': must be a number"), std::string::npos);
  EXPECT_EQ(error_of("[1, 2]"), "cases.jsonl:1: a case must be a JSON object");
}

TEST(CaseErrors, LineOfTheFieldInAMultiLineFile) {
  const std::string text = std::string("{\n  \"id\": \"t\",\n  ") + kPlanes +
                           ",\n  \"volume\": {\"sphere\": {\n    \"center\": [0, 0, 0],\n    \"radius\": -2\n  }}\n}\n";
  EXPECT_EQ(error_of(text).rfind("cases.jsonl:6: field 'volume.sphere.radius'", 0), 0u) << error_of(text);
}

TEST(CaseErrors, JsonLinesNameTheLine) {
  const fs::path dir = temp_dir();
  const fs::path file = dir / "batch.jsonl";
  {
    std::ofstream out(file);
    out << with_volume("{\"point\": [0,0,-2]}") << "\n\n"
        << with_volume("{\"point\": [0,0,-2]}") << "\n"
        << with_volume(R"({"aabb": {"min": [0,0,0], "max": [1,-1,1]}})") << "\n";
  }
  try {
    read_cases_jsonl(file);
    FAIL() << "expected a CaseError";
  } catch (const CaseError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.line(), 4);  // the blank line 2 still counts
    EXPECT_EQ(e.field(), "volume.aabb.min[1]");
  }
  fs::remove_all(dir);
}

// ---- writing ----

TEST(CaseWrite, ShortestDecimalsRoundTripBitExactly) {
  std::mt19937 rng(2024);
  for (int i = 0; i < 1000000; ++i) {
    const std::uint32_t u = rng();
    float x;
    std::memcpy(&x, &u, 4);
    if (!std::isfinite(x)) continue;
    const std::string s = format_float(x);
    ASSERT_EQ(bits(parse_case_float(s, false)), u) << s;
    ASSERT_EQ(bits(parse_case_float(format_hex_float(x), true)), u) << format_hex_float(x);
  }
  EXPECT_EQ(format_float(0.1f), "0.1");
  EXPECT_EQ(format_float(-0.0f), "-0");
  EXPECT_EQ(format_float(16777216.0f), "16777216");
}

TEST(CaseWrite, FormatThenParseGivesTheSameCase) {
  Case c;
  c.id = "rod-0007";
  c.frustum = frustum_spec(glm::mat4(1.0f), {DepthRange::zero_to_one, true});
  c.volume = Obb{{0.1f, -2.5e-7f, 3e6f}, glm::mat3(0.6f, 0.8f, 0, -0.8f, 0.6f, 0, 0, 0, 1), {1, 2, 0}};
  c.truth = Visibility::outside;
  c.note = "quote \" and newline \n";
  c.extra["distance"] = 0.125;
  for (bool pretty : {false, true}) {
    const Case d = parse_case(format_case(c, pretty));
    EXPECT_EQ(format_case(d, pretty), format_case(c, pretty));
    EXPECT_EQ(d.note, c.note);
    EXPECT_TRUE(d.frustum.depth.reversed_z);
  }
  EXPECT_EQ(format_case(c).find('\n'), std::string::npos);  // one line for JSON Lines
}

TEST(CaseWrite, AtomicWriteNeverCorruptsAnExistingFile) {
  const fs::path dir = temp_dir() / "corpus";
  const fs::path file = dir / "a.json";
  Case c;
  c.id = "a";
  c.frustum = frustum_spec(Frustum{});
  c.volume = Point{1, 2, 3};
  write_case_file(file, c);
  EXPECT_EQ(read_case_file(file).id, "a");
  Case d = c;
  d.id = "b";
  EXPECT_THROW(write_case_file(file, d, /*overwrite=*/false), std::runtime_error);
  EXPECT_EQ(read_case_file(file).id, "a");  // untouched
  write_case_file(file, d, /*overwrite=*/true);
  EXPECT_EQ(read_case_file(file).id, "b");
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) { (void)e; ++n; }
  EXPECT_EQ(n, 1u);  // no temporary file left behind
  fs::remove_all(dir.parent_path());
}
