// `cullproof classify` on hostile case files, run as a user runs it: random byte strings, and the
// hand-written cases of examples/cases.jsonl with bytes flipped, spans deleted, duplicated or cut
// off, keys and brackets changed, numbers replaced by huge, tiny, NaN-like or garbage tokens. The
// program either classifies every case (exit 0, one verdict line per case, in order) or exits
// non-zero naming the file, the line of the bad case and the field (or the JSON syntax error or the
// limit), printing no verdict for that case or any after it; it never dies of a signal or runs past
// the time limit. The inputs come from a fixed seed: the same every run.
#include "run_program.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using cullproof::testing::RunOptions;
using cullproof::testing::RunResult;
using cullproof::testing::run_program;

std::vector<std::string> example_lines() {
  std::ifstream in(fs::path(CULLPROOF_SOURCE_DIR) / "examples" / "cases.jsonl");
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

std::string id_of(const std::string& line) { return nlohmann::json::parse(line).at("id").get<std::string>(); }

// Tokens that replace a number: past float's range, below its smallest subnormal, NaN and infinity
// in the spellings people try, hex floats in and out of range, other JSON types, malformed numbers.
const std::vector<std::string>& odd_numbers() {
  static const std::vector<std::string> tokens = {
      "1e39", "-1e39", "3.4028235e38", "-3.4028235e38", "3.4028236e38", "1e-46", "-1e-45", "1e-999", "-0", "1e999",
      "-1e999", "NaN", "nan", "Infinity", "-Infinity", "inf", "\"0x1p+128\"", "\"0x1.fffffep+127\"", "\"-0x1p-149\"",
      "\"0x1p-150\"", "\"nan\"", "\"inf\"", "\"\"", "\"0x\"", "\"1.5\"", "null", "true", "[]", "{}", "[1, 2, 3]",
      "99999999999999999999999999", "18446744073709551616", "1.", ".5", "01", "--1", "1e", "0x10", "1e+", "+1",
      std::string(400, '9'), "1" + std::string(1000, '0'), "0." + std::string(1000, '0') + "1"};
  return tokens;
}

const std::vector<std::string>& keys() {
  static const std::vector<std::string> k = {"\"id\"", "\"frustum\"", "\"planes\"", "\"matrix\"", "\"depth\"",
                                             "\"volume\"", "\"aabb\"", "\"obb\"", "\"sphere\"", "\"point\"",
                                             "\"min\"", "\"max\"", "\"center\"", "\"axes\"", "\"half\"",
                                             "\"radius\"", "\"truth\"", "\"reversed_z\"", "\"Min\"", "\"\""};
  return k;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}
  std::size_t below(std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }

  std::string random_bytes() {
    std::string s(below(300), '\0');
    for (char& c : s) c = char(below(256));
    return s;
  }

  std::string mutate(std::string s) {
    const int times = 1 + int(below(2));
    for (int t = 0; t < times; ++t) s = below(2) == 0 ? in_text(std::move(s)) : in_structure(s);
    return s;
  }

 private:
  // A change to the JSON value, written back as JSON: the case stays well-formed (but for a raw
  // token such as NaN), so the reader's field checks are what meets it.
  std::string in_structure(const std::string& s) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(s, nullptr, false);
    if (j.is_discarded()) return in_text(s);
    std::vector<nlohmann::ordered_json::json_pointer> values;
    const nlohmann::ordered_json flat = j.flatten();
    for (auto it = flat.begin(); it != flat.end(); ++it) values.emplace_back(it.key());
    if (values.empty()) return in_text(s);
    auto at = values[below(values.size())];
    const std::string placeholder = "@@token@@";
    std::string raw;
    switch (below(4)) {
      case 0:
      case 1:  // a value for an odd token
        j[at] = placeholder;
        raw = odd_numbers()[below(odd_numbers().size())];
        break;
      case 2: {  // a member or an element gone, or one more
        const auto parent = at.parent_pointer();
        nlohmann::ordered_json& p = j[parent];
        if (below(2) == 0) {
          if (p.is_object()) p.erase(at.back());
          else if (p.is_array() && !p.empty()) p.erase(p.size() - 1);
        } else if (p.is_array()) {
          p.push_back(p.empty() ? nlohmann::ordered_json(0) : p.back());
        } else if (p.is_object()) {
          const std::string& key = keys()[below(keys().size())];  // quoted
          p[key.substr(1, key.size() - 2)] = 1;
        }
        break;
      }
      default: {  // an object or array around the value, or in its place
        nlohmann::ordered_json v = j[at];
        j[at] = below(2) == 0 ? nlohmann::ordered_json::array({v}) : nlohmann::ordered_json::object({{"x", v}});
        break;
      }
    }
    std::string out = j.dump();
    if (!raw.empty()) {
      const std::size_t pos = out.find("\"" + placeholder + "\"");
      if (pos != std::string::npos) out.replace(pos, placeholder.size() + 2, raw);
    }
    return out;
  }

  std::string in_text(std::string s) {
    switch (below(7)) {
      case 0: {  // flip bits
        for (std::size_t k = 0, n = 1 + below(3); k < n && !s.empty(); ++k) s[below(s.size())] ^= char(1u << below(8));
        return s;
      }
      case 1: {  // delete a span
        const std::size_t a = below(s.size()), n = 1 + below(20);
        return s.erase(a, n);
      }
      case 2: {  // duplicate a span
        const std::size_t a = below(s.size()), n = 1 + below(40);
        return s.insert(a, s.substr(a, n));
      }
      case 3:  // cut off
        return s.substr(0, below(s.size()));
      case 4:
      case 5: {  // replace numbers
        static const std::regex number(R"(-?[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?)");
        std::vector<std::pair<std::size_t, std::size_t>> spans;
        for (auto it = std::sregex_iterator(s.begin(), s.end(), number); it != std::sregex_iterator(); ++it)
          spans.emplace_back(std::size_t(it->position()), std::size_t(it->length()));
        if (spans.empty()) return s;
        for (std::size_t k = 0, n = 1 + below(3); k < n; ++k) {
          const auto [at, len] = spans[below(spans.size())];
          if (at + len > s.size()) continue;
          s.replace(at, len, odd_numbers()[below(odd_numbers().size())]);
          break;  // spans after this one have moved
        }
        return s;
      }
      default: {  // a key for another, or a bracket doubled or dropped
        if (below(2) == 0) {
          const std::string& from = keys()[below(keys().size())];
          const std::size_t at = s.find(from);
          if (at != std::string::npos) s.replace(at, from.size(), keys()[below(keys().size())]);
          return s;
        }
        std::vector<std::size_t> brackets;
        for (std::size_t i = 0; i < s.size(); ++i)
          if (s[i] == '[' || s[i] == ']' || s[i] == '{' || s[i] == '}') brackets.push_back(i);
        if (brackets.empty()) return s;
        const std::size_t at = brackets[below(brackets.size())];
        return below(2) == 0 ? s.erase(at, 1) : s.insert(at, 1, s[at]);
      }
    }
  }
  std::mt19937_64 rng_;
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

bool blank(const std::string& l) {
  return l.find_first_not_of(" \t\r\n\v\f") == std::string::npos;
}

struct Tried {
  int classified = 0, refused = 0;
};

// Runs classify on `file`, whose lines [bad_first, bad_last] (1-based) hold the hostile text and
// whose other lines are the valid cases `valid` (line number -> id). Checks the promise.
void classify_and_check(const fs::path& file, int bad_first, int bad_last, const std::vector<std::pair<int, std::string>>& valid,
                        int cases, const std::string& input, Tried& tried) {
  RunOptions o;
  o.args = {CULLPROOF_BIN, "classify", file.string()};
  const RunResult r = run_program(o);
  const std::string shown =
      "input: " + nlohmann::json(input).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
  ASSERT_FALSE(r.timed_out) << "classify ran past the time limit\n" << shown;
  ASSERT_EQ(r.signal, 0) << "classify died of signal " << r.signal << "\n" << r.err << "\n" << shown;
  const std::vector<std::string> out = lines_of(r.out);
  if (r.exit_code == 0) {
    ++tried.classified;
    ASSERT_EQ(int(out.size()), cases) << "one verdict line per case\n" << r.out << "\n" << shown;
    for (const std::string& l : out) {
      const nlohmann::json j = nlohmann::json::parse(l, nullptr, false);
      ASSERT_TRUE(j.is_object() && j.contains("verdicts") && j.contains("truth")) << l << "\n" << shown;
    }
    for (const auto& [line, id] : valid) {
      (void)line;
      bool found = false;
      for (const std::string& l : out) found = found || nlohmann::json::parse(l).at("id") == id;
      EXPECT_TRUE(found) << "no verdict for " << id << "\n" << shown;
    }
    return;
  }
  ++tried.refused;
  // "cullproof: FILE:LINE: field '...': ..." or a JSON syntax error or a limit, at the bad line.
  static const std::regex named(R"(^cullproof: (.+):([0-9]+): (field '[^']*': .+|invalid JSON: .+|arrays and objects nested deeper than .+)\n$)");
  std::smatch m;
  ASSERT_TRUE(std::regex_match(r.err, m, named)) << "exit " << r.exit_code << ", stderr does not name file, line and field:\n"
                                                 << r.err << "\n" << shown;
  EXPECT_EQ(m[1].str(), file.string());
  const int line = std::stoi(m[2].str());
  EXPECT_TRUE(line >= bad_first && line <= bad_last) << "refused line " << line << ", the hostile text is on lines "
                                                     << bad_first << "-" << bad_last << ": " << r.err << "\n" << shown;
  // Verdicts only for the valid cases before the refused line, in order.
  std::size_t k = 0;
  for (const auto& [at, id] : valid) {
    if (k == out.size()) break;
    ASSERT_LT(at, line) << "a verdict printed for a case at or after the refused line\n" << r.out << "\n" << shown;
    EXPECT_EQ(nlohmann::json::parse(out[k]).at("id"), id) << shown;
    ++k;
  }
  EXPECT_EQ(k, out.size()) << "verdicts that belong to no case before the refused line\n" << r.out << "\n" << shown;
}

class ClassifyHostile : public ::testing::Test {
 protected:

  // The hostile text alone as a one-case file, and among valid cases as JSON Lines.
  void try_both(const std::string& hostile, std::size_t n, Mutator& mut, Tried& tried) {
    const std::vector<std::string> examples = example_lines();
    {
      const fs::path f = dir_ / ("case-" + std::to_string(n) + ".json");
      std::ofstream(f, std::ios::binary) << hostile;
      classify_and_check(f, 1, std::max<int>(1, int(lines_of(hostile).size())), {}, 1, hostile, tried);
    }
    const fs::path f = dir_ / ("cases-" + std::to_string(n) + ".jsonl");
    std::vector<std::pair<int, std::string>> valid;
    std::string text;
    int line = 1, cases = 0;
    const std::size_t before = mut.below(4);
    for (std::size_t k = 0; k < before; ++k, ++line, ++cases) {
      text += examples[(n + k) % examples.size()] + "\n";
      valid.emplace_back(line, id_of(examples[(n + k) % examples.size()]));
    }
    const std::vector<std::string> hostile_lines = lines_of(hostile);
    const int first = line;
    for (const std::string& l : hostile_lines) cases += !blank(l);
    text += hostile + "\n";
    line += std::max<int>(1, int(hostile_lines.size()));
    const int last = line - 1;
    for (std::size_t k = 0; k < 2; ++k, ++line, ++cases) {
      text += examples[(n + 5 + k) % examples.size()] + "\n";
      valid.emplace_back(line, id_of(examples[(n + 5 + k) % examples.size()]));
    }
    std::ofstream(f, std::ios::binary) << text;
    classify_and_check(f, first, last, valid, cases, hostile, tried);
  }

  cullproof::testing::ScratchDir scratch_{"cullproof-classify-hostile"};
  const fs::path& dir_ = scratch_.path();
};

TEST_F(ClassifyHostile, MutatedCasesAreClassifiedOrRefusedByFileLineAndField) {
  Mutator mut(20240917);
  const std::vector<std::string> examples = example_lines();
  ASSERT_GE(examples.size(), 8u);
  Tried tried;
  for (std::size_t n = 0; n < 70; ++n) {
    try_both(mut.mutate(examples[n % examples.size()]), n, mut, tried);
    if (HasFatalFailure()) return;
  }
  // Both outcomes occur: the mutations are not all fatal, nor all harmless.
  EXPECT_GE(tried.classified, 5);
  EXPECT_GT(tried.refused, 50);
}

TEST_F(ClassifyHostile, RandomBytesAreRefusedByFileAndLine) {
  Mutator mut(7);
  Tried tried;
  for (std::size_t n = 0; n < 20; ++n) {
    try_both(mut.random_bytes(), n, mut, tried);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(tried.refused, 15);
}

}  // namespace
