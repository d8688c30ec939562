// `cullproof simulate`: the command the CLI (app/main.cpp) calls.
#include "cullproof/case_io.hpp"
#include "cullproof/simulate.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <sstream>

namespace cullproof::sim {

namespace {

void write_text(const std::string& file, const std::string& text) { write_file_atomic(file, text, true); }

}  // namespace

int run_simulate_command(const SimulateOptions& opt) {
  try {
    if (opt.table1) {
      const Table1Result t = run_table1(opt);
      print_table1(t, std::cout);
      if (!opt.json.empty()) write_text(opt.json, to_json(t).dump(1) + "\n");
      std::uint64_t forbidden = 0;
      for (const Table1Cell& c : t.cells) forbidden += c.forbidden;
      return forbidden ? 1 : 0;
    }
    if (opt.scenes.empty()) {
      std::cerr << "cullproof simulate: give a scene file (corpus/scenes/*.json) or --table1\n";
      return 2;
    }
    if (opt.scenes.size() > 1 && (!opt.csv.empty() || !opt.json.empty())) {
      std::cerr << "cullproof simulate: --csv/--json take one scene at a time\n";
      return 2;
    }
    const std::filesystem::path mesh_dir = opt.mesh_dir.empty() ? default_mesh_dir() : std::filesystem::path(opt.mesh_dir);
    std::uint64_t forbidden = 0;
    for (const std::string& file : opt.scenes) {
      const SceneDesc scene = load_scene(file);
      World world = build_world(scene, mesh_dir);
      const SimResult r = simulate(scene, world, opt);
      print_summary(r, std::cout);
      forbidden += r.forbidden_errors();
      if (!opt.csv.empty()) {
        std::ostringstream os;
        write_csv(r, os);
        write_text(opt.csv, os.str());
      }
      if (!opt.json.empty()) write_text(opt.json, to_json(r).dump(1) + "\n");
    }
    return forbidden ? 1 : 0;
  } catch (const SceneError& e) {
    std::cerr << "cullproof simulate: " << e.what() << "\n";
    return 2;
  } catch (const MeshError& e) {
    std::cerr << "cullproof simulate: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace cullproof::sim
