// keel::app::Outputs: outputs are checked when reserved, written to temporaries beside them and renamed only
// by commit(); a run that never commits leaves every existing file as it was and no temporary behind.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/outputs.hpp"

using namespace keel;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("keel_outputs_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void put(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

std::string text(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The names in `dir` (and its subfolders) that are temporaries of Outputs.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(".keel-") != std::string::npos) out.push_back(e.path().string());
  return out;
}

std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const app::OutputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("Outputs: written on commit only, with the extension kept; nothing left without commit") {
  const fs::path d = scratch("commit");
  put(d / "old.json", "{\"old\": 1}\n");
  {
    app::Outputs o;
    const fs::path t = o.file("--out", d / "old.json", app::OutputKind::json());
    CHECK(t.parent_path() == d);
    CHECK(t.extension() == ".json");
    o.write_text(d / "old.json", "{\"new\": 2}\n");
    CHECK(text(d / "old.json") == "{\"old\": 1}\n");  // not before commit()
    o.commit();
  }
  CHECK(text(d / "old.json") == "{\"new\": 2}\n");
  {
    app::Outputs o;
    (void)o.file("--out", d / "old.json", app::OutputKind::json());
    o.write_text(d / "old.json", "{\"lost\": 3}\n");
    // destroyed without commit(): the command failed
  }
  CHECK(text(d / "old.json") == "{\"new\": 2}\n");
  CHECK(temporaries(d).empty());
  {
    app::Outputs o;
    (void)o.file("--out", d / "never.json", app::OutputKind::json());
    CHECK_THROWS_AS(o.commit(), std::logic_error);  // reserved but not written
  }
  CHECK_FALSE(fs::exists(d / "never.json"));
  CHECK(temporaries(d).empty());
}

TEST_CASE("Outputs: an input, two outputs at one path, another kind and an unwritable folder are refused") {
  const fs::path d = scratch("refuse");
  put(d / "g.g2o", "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  put(d / "note.txt", "not a graph\n");
  app::Outputs o({{"file", d / "g.g2o"}, {"--pairs", d / "missing.txt"}});
  CHECK(refusal([&] {
          (void)o.file("--out", d / "." / "g.g2o", app::OutputKind::json());
        }).find("is the input file") != std::string::npos);
  CHECK(refusal([&] {
          (void)o.file("--out", d / "note.txt", app::OutputKind::graph());
        }).find("is not a pose graph") != std::string::npos);
  CHECK(refusal([&] {
          (void)o.file("--out", d / "g.g2o" / "x.json", app::OutputKind::json());
        }).find("cannot write: Not a directory") != std::string::npos);
  (void)o.file("--merged", d / "m.g2o", app::OutputKind::graph());
  CHECK(refusal([&] {
          (void)o.file("--out", d / "m.g2o", app::OutputKind::graph());
        }).find("given for two outputs (--merged and --out)") != std::string::npos);
  CHECK(text(d / "g.g2o") == "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
}

TEST_CASE(
    "Outputs: a folder output replaces only a complete earlier set; a new folder goes again on failure") {
  const fs::path d = scratch("folder");
  const std::vector<app::FolderFile> files = {{"a.csv", app::OutputKind::starting_with("x,y")},
                                              {"t.csv", app::OutputKind::starting_with("theta")}};
  {
    app::Outputs o;
    const fs::path t = o.folder("dir", d / "new" / "deeper", files);
    put(t / "a.csv", "x,y\n1,2\n");
    // not committed
  }
  CHECK_FALSE(fs::exists(d / "new"));
  {
    app::Outputs o;
    const fs::path t = o.folder("dir", d / "w", files);
    put(t / "a.csv", "x,y\n1,2\n");
    put(t / "t.csv", "theta\n0\n");
    o.commit();
  }
  CHECK(text(d / "w" / "a.csv") == "x,y\n1,2\n");
  {
    app::Outputs o;  // the complete set of an earlier run: replaced
    const fs::path t = o.folder("dir", d / "w", files);
    put(t / "a.csv", "x,y\n3,4\n");
    put(t / "t.csv", "theta\n1\n");
    o.commit();
  }
  CHECK(text(d / "w" / "a.csv") == "x,y\n3,4\n");
  fs::remove(d / "w" / "t.csv");
  app::Outputs o;
  CHECK(refusal([&] { (void)o.folder("dir", d / "w", files); }).find("refusing to replace a.csv") !=
        std::string::npos);
  CHECK(temporaries(d).empty());
}
