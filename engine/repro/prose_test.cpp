// Report prose placeholders and the literal-number scanner (core/prose.hpp).
#include <doctest/doctest.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "repro/prose.hpp"

using namespace keel::repro;

namespace {

ProseLookup fixture() {
  static const std::map<std::string, double> metrics = {
      {"pcm_exact_11.tpr", 0.940741}, {"worlds", 100000}, {"chi2", 0.0143}, {"no_out.residual", 734.3}};
  static const std::map<std::string, std::vector<double>> series = {{"tpr", {0.9975, 0.9407, 0.6634}}};
  static const std::map<std::string, double> thesis = {{"pcm_exact_11.tpr", 0.997}};
  static const std::map<std::string, double> other = {{"pcm_exact_11.fpr", 0.000741}};
  ProseLookup l;
  l.value = [](const ProseRef& r) -> std::optional<double> {
    const std::map<std::string, double>* m = nullptr;
    if (!r.experiment.empty()) {
      if (r.experiment != "ch2_table2_1_thesis_noise" || r.kind != "metric") return std::nullopt;
      m = &other;
    } else if (r.kind == "metric") {
      m = &metrics;
    } else if (r.kind == "thesis") {
      m = &thesis;
    } else if (r.kind == "series") {
      const auto it = series.find(r.key);
      if (it == series.end()) return std::nullopt;
      const auto& v = it->second;
      if (r.selector == "max") return 0.9975;
      if (r.selector == "size") return static_cast<double>(v.size());
      const std::size_t k = std::stoul(r.selector);
      if (k >= v.size()) return std::nullopt;
      return v[k];
    }
    if (!m) return std::nullopt;
    const auto it = m->find(r.key);
    if (it == m->end()) return std::nullopt;
    return it->second;
  };
  l.keys = [](const std::string&, const std::string& kind) {
    std::vector<std::string> k;
    if (kind == "metric")
      for (const auto& [key, v] : metrics) k.push_back(key);
    return k;
  };
  return l;
}

std::vector<std::string> literals(std::string_view text) {
  std::vector<std::string> out;
  for (const auto& n : literal_numbers(text)) out.push_back(n.text);
  return out;
}

}  // namespace

TEST_CASE("placeholders are filled from the results with their format") {
  const auto l = fixture();
  CHECK(expand_prose("TPR {metric:pcm_exact_11.tpr} (thesis {thesis:pcm_exact_11.tpr})", l, "t") ==
        "TPR 0.941 (thesis 0.997)");
  CHECK(expand_prose("{metric:pcm_exact_11.tpr|.1%} of inliers", l, "t") == "94.1 % of inliers");
  CHECK(expand_prose("on {metric:worlds|d} worlds", l, "t") == "on 100\u2009000 worlds");
  CHECK(expand_prose("Σχ² ≈ {metric:no_out.residual|.0f}", l, "t") == "Σχ² ≈ 734");
  CHECK(expand_prose("FPR {ch2_table2_1_thesis_noise/metric:pcm_exact_11.fpr|.1e}", l, "t") == "FPR 7.4e-04");
  CHECK(expand_prose("{series:tpr[1]|.3f} at 11 %, best {series:tpr[max]}", l, "t") ==
        "0.941 at 11 %, best 0.998");
  CHECK(expand_prose("a literal {{ brace", l, "t") == "a literal { brace");
  CHECK(expand_prose("no placeholder", l, "t") == "no placeholder");
}

TEST_CASE("a placeholder that does not resolve is an error naming it and the nearest key") {
  const auto l = fixture();
  CHECK_THROWS_WITH_AS(
      (void)expand_prose("TPR {metric:pcm_exact_11.tp}", l, "x.toml discussion"),
      "x.toml discussion: placeholder '{metric:pcm_exact_11.tp}': no metric 'pcm_exact_11.tp' "
      "(nearest: 'pcm_exact_11.tpr')",
      std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("{metrik:chi2}", l, "t"),
                       doctest::Contains("unknown kind 'metrik'"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("{metric:chi2|.3x}", l, "t"),
                       doctest::Contains("unknown number format '.3x'"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("{series:tpr}", l, "t"),
                       doctest::Contains("a series needs a selector"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("{series:tpr[7]}", l, "t"), doctest::Contains("no series 'tpr'"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("open {metric:chi2", l, "t"),
                       doctest::Contains("unclosed placeholder"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)expand_prose("{other/thesis:x}", l, "t"),
                       doctest::Contains("this experiment only"), std::invalid_argument);
  auto lenient = l;
  lenient.missing_text = "n/a";
  CHECK(expand_prose("TPR {metric:missing} here", lenient, "t") == "TPR n/a here");
  CHECK_THROWS_WITH_AS((void)expand_prose("{metrik:chi2}", lenient, "t"), doctest::Contains("unknown kind"),
                       std::invalid_argument);
  CHECK(prose_placeholders("{a/metric:x} and {series:y[min]|.2f}", "t").size() == 2);
}

TEST_CASE("number formats") {
  CHECK(format_prose_number(0.000741, ".2g") == "0.00074");
  CHECK(format_prose_number(2.5, ".0f") == "2");
  CHECK(format_prose_number(-1234567, "d") == "−1\u2009234\u2009567");
  CHECK(format_prose_number(1500, "d") == "1500");  // four digits are not grouped
  CHECK(format_prose_number(0.5, ".0%") == "50 %");
}

TEST_CASE("literal numbers: values are found, structural references are not") {
  CHECK(literals("TPR 0.941 against 0.997, 8100 outliers") ==
        std::vector<std::string>{"0.941", "0.997", "8100"});
  CHECK(literals("on 100 000 worlds") == std::vector<std::string>{"100 000"});
  CHECK(literals("error 2.75e-4 at α = 1") == std::vector<std::string>{"2.75e-4", "1"});
  CHECK(literals("a rate of 2–39 %") == std::vector<std::string>{"2", "39"});
  CHECK(literals("Table 2.1 and Fig. 2.4, Figs. 5.10–5.14, eq. 2.5, §2.6 and §5.9.2") ==
        std::vector<std::string>{});
  CHECK(literals("Tables 5.1 and 5.2 agree") == std::vector<std::string>{});
  CHECK(literals("poses in SE(3) and SO(2), the 1D world, 3D maps, ε (5.56)") == std::vector<std::string>{});
  CHECK(literals("the key `s0_12.tpr` and x1, m0020") == std::vector<std::string>{});
  CHECK(literals("{metric:chi2} and {{ 4 }}") == std::vector<std::string>{"4"});
  CHECK(literals("a 2-core machine, 8× less noise") == std::vector<std::string>{"2", "8"});
  CHECK(literals("PCM-Exact-11 % and RANSAC-1 %, an order-1 bound") == std::vector<std::string>{});
  CHECK(literals("escalation to order 2, then 3 more") == std::vector<std::string>{"3"});
  CHECK(literals("a 6×6 block, headings at multiples of π/2, 3 × 4") == std::vector<std::string>{"3", "4"});
  CHECK(literal_numbers("x = -0.5")[0].value == -0.5);
}

TEST_CASE("a literal matches a value to its own precision, or as a percentage") {
  auto lit = [](const char* text) { return literal_numbers(text).at(0); };
  CHECK(literal_matches(lit("0.941"), 0.940741));
  CHECK_FALSE(literal_matches(lit("0.94"), 0.9349));
  CHECK(literal_matches(lit("94.1"), 0.940741));  // "94.1 %"
  CHECK(literal_matches(lit("8100"), 8100));
  CHECK_FALSE(literal_matches(lit("8100"), 8101));
  CHECK(literal_matches(lit("2.75e-4"), 0.000275));
  CHECK_FALSE(literal_matches(lit("2.75e-4"), 0.000277));
}
