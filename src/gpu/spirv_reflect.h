// A small SPIR-V reader: compute local size, push-constant block size, storage bindings and named struct layouts.
//
// It reads only what dentsim checks at run time and in the layout pin test; it is no validator.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim::gpu {

// One dimension of the local size: a literal, or a specialization constant with its default.
struct LocalSizeDim {
  uint32_t value = 1;     // the literal or the spec constant's default [invocations]
  int32_t spec_id = -1;   // SpecId when the size comes from a specialization constant, else -1
};

struct StructMember {
  std::string name;   // OpMemberName, or "" when stripped
  uint32_t offset;    // Offset decoration [B]
  uint32_t size;      // size of the member's type [B]
};

struct ShaderReflection {
  std::array<LocalSizeDim, 3> local_size{};  // of the first GLCompute entry point
  uint32_t push_constant_size = 0;           // size of the push-constant block [B]; 0 if none
  std::vector<uint32_t> storage_bindings;    // bindings of storage buffers in descriptor set 0, sorted

  // Members of the struct type named `name` (OpName) that carries Offset decorations, i.e. the
  // layout the shader really uses; nullopt when the module has no such struct.
  std::optional<std::vector<StructMember>> structLayout(const std::string& name) const;

  struct NamedStruct {
    std::string name;
    std::vector<StructMember> members;
  };
  std::vector<NamedStruct> structs;  // every named struct type whose members all carry offsets
};

// Reads `words` (a whole module). Errors name the problem: bad magic, truncated instruction,
// no GLCompute entry point, a size that depends on an unknown constant.
Result<ShaderReflection> reflectSpirv(std::span<const uint32_t> words);

// The local size with specialization applied: dims whose spec_id appears in `spec` take its value.
struct SpecValue {
  uint32_t id;
  uint32_t value;
};
std::array<uint32_t, 3> specializedLocalSize(const ShaderReflection& r, std::span<const SpecValue> spec);

}  // namespace dentsim::gpu
