// `dentsim make-tooth [--out DIR]`: regenerates the built-in molar and tools and writes them under DIR (assets/).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "io/atomic_file.h"
#include "model/builtin_assets.h"
#include "model/tool_generator.h"

namespace dentsim::app {
namespace {

struct MakeToothOptions {
  std::string out = "assets";  // the assets folder to write into (the source tree's assets/ to update it)
  double grid_mm = MolarOptions{}.grid_mm;  // lattice spacing [mm]; only the default reproduces the checked-in files
};

void printMesh(const char* what, const TriangleMesh& m) {
  std::printf("  %-20s %8zu triangles  %9.2f mm^3\n", what, m.triangleCount(), m.signedVolume());
}

int runMakeTooth(const MakeToothOptions& o) {
  MolarOptions mo;
  mo.grid_mm = o.grid_mm;
  const GeneratedAssets g = generateAssets(mo);
  const std::filesystem::path root(o.out);
  for (const AssetFile& f : g.files) {
    const std::filesystem::path path = root / f.path;
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) return fail(path.parent_path().string() + ": " + ec.message());
    // Each file is replaced atomically, so an interrupted run leaves whole old or whole new files.
    if (Status s = writeFileAtomic(path.string(), f.bytes); !s) return fail(s.message());
  }
  std::printf("molar (grid %.3g mm) -> %s/teeth\n", o.grid_mm, o.out.c_str());
  printMesh("enamel", g.molar.enamel);
  printMesh("dentin (incl. pulp)", g.molar.dentin);
  printMesh("pulp", g.molar.pulp);
  printMesh("caries", g.molar.caries);
  std::printf("  tooth volume %.2f mm^3 (enamel + dentin)\n", g.molar.enamel.signedVolume() + g.molar.dentin.signedVolume());
  std::printf("tools -> %s/tools\n", o.out.c_str());
  const auto tools = toolCatalog();
  for (size_t i = 0; i < tools.size(); ++i) printMesh(tools[i].name, g.tools[i]);
  std::printf("wrote %zu files\n", g.files.size());
  return 0;
}

}  // namespace

void addMakeToothCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<MakeToothOptions>();
  CLI::App* cmd = root.add_subcommand("make-tooth", "Regenerate the built-in molar (4 STL layers) and tool meshes");
  cmd->add_option("--out", opts->out, "Assets folder to write teeth/ and tools/ into")->capture_default_str();
  cmd->add_option("--grid", opts->grid_mm, "Lattice spacing of the molar [mm]")
      ->check(finiteIn(0.05, 1.0, "mm"))
      ->capture_default_str();
  cmd->callback([opts, &action] { action = [opts] { return runMakeTooth(*opts); }; });
}

}  // namespace dentsim::app
