// SPIR-V reader for the checks dentsim makes: local size, push-constant size, bindings, struct member offsets.
//
// Written from the SPIR-V specification (section 2.3 physical layout, 3 enumerants, 3.49 instructions).
// One pass collects names, decorations, types and constants; sizes are computed afterwards because
// decorations come before the types they decorate.
#include "gpu/spirv_reflect.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace dentsim::gpu {
namespace {

// Opcodes and enumerants used here (SPIR-V spec, section 3).
enum : uint32_t {
  kMagic = 0x07230203u,
  OpName = 5, OpMemberName = 6, OpEntryPoint = 15, OpExecutionMode = 16,
  OpTypeBool = 20, OpTypeInt = 21, OpTypeFloat = 22, OpTypeVector = 23, OpTypeMatrix = 24,
  OpTypeArray = 28, OpTypeRuntimeArray = 29, OpTypeStruct = 30, OpTypePointer = 32,
  OpConstant = 43, OpConstantComposite = 44, OpSpecConstant = 50, OpSpecConstantComposite = 51,
  OpVariable = 59, OpDecorate = 71, OpMemberDecorate = 72, OpExecutionModeId = 331,
  ExecModelGLCompute = 5, ModeLocalSize = 17, ModeLocalSizeId = 38,
  DecSpecId = 1, DecBlock = 2, DecBufferBlock = 3, DecArrayStride = 6, DecMatrixStride = 7, DecBuiltIn = 11,
  DecBinding = 33, DecDescriptorSet = 34, DecOffset = 35,
  BuiltInWorkgroupSize = 25,
  StorageUniform = 2, StoragePushConstant = 9, StorageStorageBuffer = 12,
};

struct Type {
  uint32_t op = 0;
  uint32_t width = 0;              // int/float [bits]
  uint32_t element = 0;            // vector component, matrix column, array element, pointee
  uint32_t count = 0;              // vector components, matrix columns
  uint32_t length_id = 0;          // array length constant
  uint32_t storage = 0;            // pointer storage class
  std::vector<uint32_t> members;   // struct member types
};

Type typeOf(uint32_t op) {
  Type t;
  t.op = op;
  return t;
}

struct Constant {
  uint32_t value = 0;                 // low 32 bits of a scalar
  std::vector<uint32_t> constituents; // composite
  bool spec = false;
};

struct Module {
  std::unordered_map<uint32_t, std::string> names;
  std::map<std::pair<uint32_t, uint32_t>, std::string> member_names;
  std::unordered_map<uint32_t, Type> types;
  std::unordered_map<uint32_t, Constant> constants;
  std::unordered_map<uint32_t, uint32_t> spec_ids, array_strides, bindings, sets;
  std::unordered_map<uint32_t, bool> buffer_blocks;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> member_offsets, matrix_strides;
  uint32_t workgroup_size_id = 0;
  struct Variable {
    uint32_t pointer_type, id, storage;
  };
  std::vector<Variable> variables;
  uint32_t entry = 0;
  bool has_entry = false;
  std::vector<uint32_t> local_size_literal, local_size_ids;
};

// A nul-terminated literal string packed little-endian into words [begin, end).
std::string readString(std::span<const uint32_t> w, size_t begin, size_t end, size_t* words_used = nullptr) {
  std::string s;
  size_t i = begin;
  for (; i < end; ++i) {
    bool done = false;
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((w[i] >> (8 * b)) & 0xffu);
      if (c == '\0') { done = true; break; }
      s.push_back(c);
    }
    if (done) { ++i; break; }
  }
  if (words_used) *words_used = i - begin;
  return s;
}

Result<Module> parse(std::span<const uint32_t> w) {
  const std::string where = "spirv";
  if (w.size() < 5) return makeError(where, "module shorter than its 5-word header");
  if (w[0] != kMagic) return makeError(where, "bad magic number (not a SPIR-V module, or wrong endianness)");
  Module m;
  for (size_t at = 5; at < w.size();) {
    const uint32_t count = w[at] >> 16;
    const uint32_t op = w[at] & 0xffffu;
    if (count == 0 || at + count > w.size())
      return makeError(where, "truncated instruction at word " + std::to_string(at));
    const std::span<const uint32_t> in = w.subspan(at, count);
    auto arg = [&](size_t i) { return i < in.size() ? in[i] : 0u; };
    switch (op) {
      case OpName: m.names[arg(1)] = readString(in, 2, in.size()); break;
      case OpMemberName: m.member_names[{arg(1), arg(2)}] = readString(in, 3, in.size()); break;
      case OpEntryPoint:
        if (arg(1) == ExecModelGLCompute && !m.has_entry) { m.entry = arg(2); m.has_entry = true; }
        break;
      case OpExecutionMode:
      case OpExecutionModeId:
        // Modes may precede nothing else, but the entry point is declared first (spec 2.4).
        if (m.has_entry && arg(1) == m.entry && in.size() >= 6) {
          std::vector<uint32_t> xyz{arg(3), arg(4), arg(5)};
          if (arg(2) == ModeLocalSize) m.local_size_literal = xyz;
          if (arg(2) == ModeLocalSizeId) m.local_size_ids = xyz;
        }
        break;
      case OpTypeBool: m.types[arg(1)] = typeOf(op); break;
      case OpTypeInt:
      case OpTypeFloat: { Type t = typeOf(op); t.width = arg(2); m.types[arg(1)] = t; break; }
      case OpTypeVector:
      case OpTypeMatrix: { Type t = typeOf(op); t.element = arg(2); t.count = arg(3); m.types[arg(1)] = t; break; }
      case OpTypeArray: { Type t = typeOf(op); t.element = arg(2); t.length_id = arg(3); m.types[arg(1)] = t; break; }
      case OpTypeRuntimeArray: { Type t = typeOf(op); t.element = arg(2); m.types[arg(1)] = t; break; }
      case OpTypeStruct: { Type t = typeOf(op); t.members.assign(in.begin() + 2, in.end()); m.types[arg(1)] = t; break; }
      case OpTypePointer: { Type t = typeOf(op); t.storage = arg(2); t.element = arg(3); m.types[arg(1)] = t; break; }
      case OpConstant:
      case OpSpecConstant: { Constant c; c.value = arg(3); c.spec = op == OpSpecConstant; m.constants[arg(2)] = c; break; }
      case OpConstantComposite:
      case OpSpecConstantComposite: {
        Constant c;
        c.constituents.assign(in.begin() + 3, in.end());
        c.spec = op == OpSpecConstantComposite;
        m.constants[arg(2)] = c;
        break;
      }
      case OpVariable: m.variables.push_back({arg(1), arg(2), arg(3)}); break;
      case OpDecorate:
        switch (arg(2)) {
          case DecSpecId: m.spec_ids[arg(1)] = arg(3); break;
          case DecArrayStride: m.array_strides[arg(1)] = arg(3); break;
          case DecBinding: m.bindings[arg(1)] = arg(3); break;
          case DecDescriptorSet: m.sets[arg(1)] = arg(3); break;
          case DecBufferBlock: m.buffer_blocks[arg(1)] = true; break;
          case DecBuiltIn: if (arg(3) == BuiltInWorkgroupSize) m.workgroup_size_id = arg(1); break;
          default: break;
        }
        break;
      case OpMemberDecorate:
        if (arg(3) == DecOffset) m.member_offsets[{arg(1), arg(2)}] = arg(4);
        if (arg(3) == DecMatrixStride) m.matrix_strides[{arg(1), arg(2)}] = arg(4);
        break;
      default: break;
    }
    at += count;
  }
  if (!m.has_entry) return makeError(where, "no GLCompute entry point");
  return m;
}

// Size of a type as laid out in a block [B]; nullopt when it has no fixed size here.
std::optional<uint32_t> typeSize(const Module& m, uint32_t id, int depth = 0);

std::optional<uint32_t> memberSize(const Module& m, uint32_t struct_id, uint32_t index, uint32_t type_id, int depth) {
  const auto t = m.types.find(type_id);
  if (t != m.types.end() && t->second.op == OpTypeMatrix) {
    const auto stride = m.matrix_strides.find({struct_id, index});
    if (stride == m.matrix_strides.end()) return std::nullopt;
    return t->second.count * stride->second;
  }
  return typeSize(m, type_id, depth + 1);
}

std::optional<uint32_t> typeSize(const Module& m, uint32_t id, int depth) {
  if (depth > 32) return std::nullopt;  // a malformed, cyclic module
  const auto it = m.types.find(id);
  if (it == m.types.end()) return std::nullopt;
  const Type& t = it->second;
  switch (t.op) {
    case OpTypeInt:
    case OpTypeFloat: return t.width / 8;
    case OpTypeVector: {
      const auto c = typeSize(m, t.element, depth + 1);
      if (!c) return std::nullopt;
      return *c * t.count;
    }
    case OpTypeArray: {
      const auto len = m.constants.find(t.length_id);
      if (len == m.constants.end()) return std::nullopt;
      if (const auto stride = m.array_strides.find(id); stride != m.array_strides.end())
        return len->second.value * stride->second;
      const auto e = typeSize(m, t.element, depth + 1);
      if (!e) return std::nullopt;
      return len->second.value * *e;
    }
    case OpTypeRuntimeArray: return 0u;  // unsized: adds nothing to a block's fixed size
    case OpTypeStruct: {
      uint32_t end = 0;
      for (uint32_t i = 0; i < t.members.size(); ++i) {
        const auto off = m.member_offsets.find({id, i});
        if (off == m.member_offsets.end()) return std::nullopt;
        const auto s = memberSize(m, id, i, t.members[i], depth);
        if (!s) return std::nullopt;
        end = std::max(end, off->second + *s);
      }
      return end;
    }
    default: return std::nullopt;
  }
}

// Value and spec id of a constant used as a local size.
std::optional<LocalSizeDim> constantDim(const Module& m, uint32_t id) {
  const auto c = m.constants.find(id);
  if (c == m.constants.end() || !c->second.constituents.empty()) return std::nullopt;
  LocalSizeDim d;
  d.value = c->second.value;
  if (c->second.spec) {
    const auto s = m.spec_ids.find(id);
    if (s != m.spec_ids.end()) d.spec_id = static_cast<int32_t>(s->second);
  }
  return d;
}

}  // namespace

Result<ShaderReflection> reflectSpirv(std::span<const uint32_t> words) {
  auto parsed = parse(words);
  if (!parsed) return parsed.error();
  const Module& m = *parsed;
  ShaderReflection r;
  const std::string where = "spirv";

  // Local size: a WorkgroupSize built-in overrides the execution modes (spec 14.6, WorkgroupSize).
  std::vector<uint32_t> size_ids = m.local_size_ids;
  if (m.workgroup_size_id) {
    const auto c = m.constants.find(m.workgroup_size_id);
    if (c == m.constants.end() || c->second.constituents.size() != 3)
      return makeError(where, "WorkgroupSize built-in is not a 3-component constant");
    size_ids = c->second.constituents;
  }
  if (!size_ids.empty()) {
    for (size_t i = 0; i < 3; ++i) {
      const auto d = constantDim(m, size_ids[i]);
      if (!d) return makeError(where, "local size refers to an unknown constant %" + std::to_string(size_ids[i]));
      r.local_size[i] = *d;
    }
  } else if (!m.local_size_literal.empty()) {
    for (size_t i = 0; i < 3; ++i) r.local_size[i].value = m.local_size_literal[i];
  } else {
    return makeError(where, "compute entry point has no local size");
  }

  // Push constants and storage buffers from the module's variables.
  for (const auto& v : m.variables) {
    const auto ptr = m.types.find(v.pointer_type);
    if (ptr == m.types.end() || ptr->second.op != OpTypePointer) continue;
    const uint32_t pointee = ptr->second.element;
    if (v.storage == StoragePushConstant) {
      const auto size = typeSize(m, pointee);
      if (!size) return makeError(where, "push-constant block has a member of unknown size");
      r.push_constant_size = std::max(r.push_constant_size, *size);
    }
    const bool storage = v.storage == StorageStorageBuffer ||
                         (v.storage == StorageUniform && m.buffer_blocks.count(pointee) != 0);
    if (storage) {
      const auto set = m.sets.find(v.id);
      const auto binding = m.bindings.find(v.id);
      if (binding != m.bindings.end() && (set == m.sets.end() || set->second == 0))
        r.storage_bindings.push_back(binding->second);
    }
  }
  std::sort(r.storage_bindings.begin(), r.storage_bindings.end());

  // Named structs with explicit offsets: the layouts the shader uses in blocks.
  for (const auto& [id, t] : m.types) {
    if (t.op != OpTypeStruct) continue;
    const auto n = m.names.find(id);
    if (n == m.names.end() || n->second.empty()) continue;
    ShaderReflection::NamedStruct s{n->second, {}};
    bool complete = true;
    for (uint32_t i = 0; i < t.members.size() && complete; ++i) {
      const auto off = m.member_offsets.find({id, i});
      const auto size = memberSize(m, id, i, t.members[i], 0);
      if (off == m.member_offsets.end() || !size) { complete = false; break; }
      const auto mn = m.member_names.find({id, i});
      s.members.push_back({mn == m.member_names.end() ? std::string() : mn->second, off->second, *size});
    }
    if (complete && !t.members.empty()) r.structs.push_back(std::move(s));
  }
  std::sort(r.structs.begin(), r.structs.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return r;
}

std::optional<std::vector<StructMember>> ShaderReflection::structLayout(const std::string& name) const {
  for (const auto& s : structs)
    if (s.name == name) return s.members;
  return std::nullopt;
}

std::array<uint32_t, 3> specializedLocalSize(const ShaderReflection& r, std::span<const SpecValue> spec) {
  std::array<uint32_t, 3> out{};
  for (size_t i = 0; i < 3; ++i) {
    out[i] = r.local_size[i].value;
    for (const SpecValue& s : spec)
      if (r.local_size[i].spec_id >= 0 && s.id == static_cast<uint32_t>(r.local_size[i].spec_id)) out[i] = s.value;
  }
  return out;
}

}  // namespace dentsim::gpu
