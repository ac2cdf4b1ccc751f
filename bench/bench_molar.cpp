// loadBenchMolar: the embedded molar, or the generator's while assets/ holds none.
#include "bench/bench_molar.h"

#include <utility>

#include "model/builtin_assets.h"
#include "sim/builtin_tooth.h"

namespace dentsim::bench {

std::vector<MeshLayer> BenchMolar::layers() const { return builtinMolarLayers(molar); }

Bounds3 BenchMolar::bounds() const {
  Bounds3 b;
  for (const MeshLayer& l : layers()) b.add(l.mesh->bounds());
  return b;
}

BenchMolar loadBenchMolar() {
  BenchMolar m;
  if (auto loaded = loadBuiltinMolar()) {
    m.molar = std::move(loaded).value();
    m.description = "built-in four-layer molar (assets/teeth/molar_*.stl)";
  } else {
    m.molar = generateMolar();
    m.description = "four-layer molar from generateMolar() (assets/ held none: " + loaded.message() + ")";
  }
  return m;
}

}  // namespace dentsim::bench
