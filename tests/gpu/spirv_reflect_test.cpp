// Tests of src/gpu/spirv_reflect.cpp, including the layout pin: GLSL offsets of the shared structs equal C++ offsetof.
#include <gtest/gtest.h>

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

#include "dentsim_compute_spirv_named.h"
#include "dentsim_compute_spirv_spirv.h"
#include "gpu/spirv_reflect.h"
#include "volume/brick_layout.h"

namespace dentsim::gpu::test {
namespace {

using layout::GridInfo;
using layout::MaterialCountParams;

// A hand-assembled module, so that reflection of LocalSizeId, spec constants, nested structs and
// strided arrays is tested on exact, known words.
class ModuleBuilder {
 public:
  // Appends one instruction: its operands, then `text` as a nul-terminated literal string.
  void op(uint32_t opcode, std::initializer_list<uint32_t> args, const std::string& text = {}) {
    std::vector<uint32_t> body(args);
    if (!text.empty()) {
      std::vector<uint32_t> packed((text.size() + 4) / 4, 0u);
      for (size_t i = 0; i < text.size(); ++i) packed[i / 4] |= uint32_t(uint8_t(text[i])) << (8 * (i % 4));
      body.insert(body.end(), packed.begin(), packed.end());
    }
    words_.push_back((uint32_t(body.size() + 1) << 16) | opcode);
    words_.insert(words_.end(), body.begin(), body.end());
  }
  std::vector<uint32_t> words() const {
    std::vector<uint32_t> w{0x07230203u, 0x00010500u, 0u, 100u, 0u};
    w.insert(w.end(), words_.begin(), words_.end());
    return w;
  }

 private:
  std::vector<uint32_t> words_;
};

std::vector<uint32_t> handModule() {
  ModuleBuilder b;
  b.op(15, {5, 1}, "main");           // OpEntryPoint GLCompute %1 "main"
  b.op(331, {1, 38, 10, 11, 12});           // OpExecutionModeId %1 LocalSizeId %10 %11 %12
  b.op(5, {20}, "Inner");             // OpName %20 "Inner"
  b.op(6, {20, 0}, "a");              // OpMemberName %20 0 "a"
  b.op(6, {20, 1}, "b");
  b.op(71, {11, 1, 7});                     // OpDecorate %11 SpecId 7
  b.op(71, {30, 6, 16});                    // OpDecorate %30 ArrayStride 16
  b.op(72, {20, 0, 35, 0});                 // Inner.a   Offset 0
  b.op(72, {20, 1, 35, 16});                // Inner.b   Offset 16
  b.op(72, {40, 0, 35, 0});                 // Outer.in  Offset 0
  b.op(72, {40, 1, 35, 32});                // Outer.arr Offset 32
  b.op(72, {40, 2, 35, 80});                // Outer.tail Offset 80
  b.op(21, {2, 32, 0});                     // %2 = uint
  b.op(22, {3, 32});                        // %3 = float
  b.op(23, {4, 3, 3});                      // %4 = vec3 (12 B)
  b.op(43, {2, 10, 32});                    // %10 = 32
  b.op(50, {2, 11, 4});                     // %11 = spec constant, default 4
  b.op(43, {2, 12, 1});                     // %12 = 1
  b.op(43, {2, 13, 3});                     // %13 = 3
  b.op(28, {30, 4, 13});                    // %30 = vec3[3], stride 16: 48 B
  b.op(30, {20, 2, 4});                     // %20 = Inner { uint a; vec3 b; }: 28 B
  b.op(30, {40, 20, 30, 2});                // %40 = Outer { Inner in; vec3 arr[3]; uint tail; }: 84 B
  b.op(32, {41, 9, 40});                    // %41 = pointer PushConstant Outer
  b.op(59, {41, 42, 9});                    // %42 = variable PushConstant
  return b.words();
}

void expectMember(const std::vector<StructMember>& members, size_t i, const char* name, size_t offset, size_t size) {
  ASSERT_LT(i, members.size());
  EXPECT_EQ(members[i].name, name);
  EXPECT_EQ(members[i].offset, offset) << name;
  EXPECT_EQ(members[i].size, size) << name;
}

}  // namespace

TEST(SpirvReflectTest, MaterialCountsLocalSizePushConstantsAndBindings) {
  auto r = reflectSpirv({material_counts_comp_spv, material_counts_comp_spv_words});
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->local_size[0].value, DS_COUNT_GROUP_SIZE);
  EXPECT_EQ(r->local_size[1].value, 1u);
  EXPECT_EQ(r->local_size[2].value, 1u);
  EXPECT_EQ(r->push_constant_size, sizeof(MaterialCountParams));
  EXPECT_EQ(r->storage_bindings, (std::vector<uint32_t>{DS_BINDING_CHUNKS, DS_BINDING_BLOCKS, DS_BINDING_BRICKS,
                                                        DS_BINDING_COUNT_OUT}));
}

// The layout pin: GridInfo and MaterialCountParams are declared once, in brick_layout.h; this proves
// glslang lays them out as the C++ compiler does.
TEST(SpirvReflectTest, GlslOffsetsOfSharedStructsEqualCppOffsetof) {
  auto r = reflectSpirv({material_counts_named_spv, material_counts_named_spv_words});
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->push_constant_size, sizeof(MaterialCountParams));

  const auto grid = r->structLayout("GridInfo");
  ASSERT_TRUE(grid.has_value()) << "GridInfo with offsets not found in the module";
  ASSERT_EQ(grid->size(), 4u);
  expectMember(*grid, 0, "level", offsetof(GridInfo, level), sizeof(GridInfo::level));
  expectMember(*grid, 1, "brickDim", offsetof(GridInfo, brickDim), sizeof(GridInfo::brickDim));
  expectMember(*grid, 2, "chunkDim", offsetof(GridInfo, chunkDim), sizeof(GridInfo::chunkDim));
  expectMember(*grid, 3, "brickCount", offsetof(GridInfo, brickCount), sizeof(GridInfo::brickCount));

  const auto params = r->structLayout("MaterialCountParams");
  ASSERT_TRUE(params.has_value()) << "MaterialCountParams with offsets not found in the module";
  ASSERT_EQ(params->size(), 5u);
  expectMember(*params, 0, "grid", offsetof(MaterialCountParams, grid), sizeof(GridInfo));
  expectMember(*params, 1, "firstBrick", offsetof(MaterialCountParams, firstBrick), 4);
  expectMember(*params, 2, "brickLimit", offsetof(MaterialCountParams, brickLimit), 4);
  expectMember(*params, 3, "pad0", offsetof(MaterialCountParams, pad0), 4);
  expectMember(*params, 4, "pad1", offsetof(MaterialCountParams, pad1), 4);
}

TEST(SpirvReflectTest, LocalSizeIdWithSpecConstantsNestedStructsAndStridedArrays) {
  const auto words = handModule();
  auto r = reflectSpirv(words);
  ASSERT_TRUE(r) << r.message();
  EXPECT_EQ(r->local_size[0].value, 32u);
  EXPECT_EQ(r->local_size[0].spec_id, -1);
  EXPECT_EQ(r->local_size[1].value, 4u);
  EXPECT_EQ(r->local_size[1].spec_id, 7);
  EXPECT_EQ(r->local_size[2].value, 1u);
  EXPECT_EQ(r->push_constant_size, 84u);  // tail at 80 + 4
  const auto inner = r->structLayout("Inner");
  ASSERT_TRUE(inner.has_value());
  ASSERT_EQ(inner->size(), 2u);
  expectMember(*inner, 0, "a", 0, 4);
  expectMember(*inner, 1, "b", 16, 12);

  const SpecValue spec[] = {{7, 16}, {3, 99}};
  EXPECT_EQ(specializedLocalSize(*r, spec), (std::array<uint32_t, 3>{32, 16, 1}));
  EXPECT_EQ(specializedLocalSize(*r, {}), (std::array<uint32_t, 3>{32, 4, 1}));
}

TEST(SpirvReflectTest, MalformedModulesAreErrors) {
  auto words = handModule();
  auto bad_magic = words;
  bad_magic[0] = 0x03022307u;
  auto a = reflectSpirv(bad_magic);
  ASSERT_FALSE(a);
  EXPECT_NE(a.message().find("magic"), std::string::npos) << a.message();

  auto truncated = words;
  truncated.pop_back();  // the last instruction now runs past the end
  auto b = reflectSpirv(truncated);
  ASSERT_FALSE(b);
  EXPECT_NE(b.message().find("truncated"), std::string::npos) << b.message();

  auto c = reflectSpirv(std::span<const uint32_t>(words).first(3));
  EXPECT_FALSE(c);
}

}  // namespace dentsim::gpu::test
