#include "gpu/spirv_reflect.h"
#include "core/error.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace aquaform::gpu {

namespace {

// Opcodes, decorations and storage classes of the SPIR-V specification (unified 1.6).
constexpr uint32_t kMagic = 0x07230203;
constexpr uint32_t kOpName = 5, kOpMemberName = 6, kOpTypeImage = 25, kOpTypeStruct = 30, kOpTypePointer = 32,
                   kOpVariable = 59, kOpDecorate = 71, kOpMemberDecorate = 72;
constexpr uint32_t kDecorationBufferBlock = 3, kDecorationNonWritable = 24, kDecorationNonReadable = 25,
                   kDecorationBinding = 33, kDecorationDescriptorSet = 34;
constexpr uint32_t kStorageUniformConstant = 0, kStorageUniform = 2, kStorageBuffer = 12;
constexpr uint32_t kDimBuffer = 5, kSampledStorage = 2;  // OpTypeImage's Dim and Sampled operands

struct Id {
    std::string name;
    std::vector<std::string> member_names;
    uint32_t members = 0;
    std::vector<bool> member_non_writable, member_non_readable;
    bool non_writable = false, non_readable = false, buffer_block = false;
    int binding = -1, set = 0;
    uint32_t pointee = 0, storage = ~0u;  // OpTypePointer / OpVariable
    uint32_t type = 0;                    // OpVariable's pointer type
    bool variable = false, pointer = false;
    uint32_t texel_format = 0;  // OpTypeImage of a storage texel buffer: its image format
};

std::string literal(std::span<const uint32_t> words) {
    std::string s;
    for (uint32_t w : words)
        for (int i = 0; i < 4; ++i) {
            const char c = char((w >> (8 * i)) & 0xff);
            if (c == 0) return s;
            s += c;
        }
    return s;
}

void set_flag(std::vector<bool>& flags, uint32_t member) {
    if (flags.size() <= member) flags.resize(member + 1, false);
    flags[member] = true;
}

}  // namespace

std::vector<ShaderBinding> reflect_bindings(std::span<const uint32_t> spirv, std::string_view shader) {
    if (spirv.size() < 5 || spirv[0] != kMagic) throw Failure(std::string(shader) + ": not a SPIR-V module");
    std::unordered_map<uint32_t, Id> ids;
    for (size_t at = 5; at < spirv.size();) {
        const uint32_t op = spirv[at] & 0xffff, count = spirv[at] >> 16;
        if (count == 0 || at + count > spirv.size())
            throw Failure(std::string(shader) + ": truncated SPIR-V instruction");
        const std::span<const uint32_t> w = spirv.subspan(at, count);
        switch (op) {
            case kOpName:
                ids[w[1]].name = literal(w.subspan(2));
                break;
            case kOpMemberName: {
                Id& id = ids[w[1]];
                if (id.member_names.size() <= w[2]) id.member_names.resize(w[2] + 1);
                id.member_names[w[2]] = literal(w.subspan(3));
                break;
            }
            case kOpTypeStruct:
                ids[w[1]].members = count - 2;
                break;
            case kOpTypeImage:
                // A storage texel buffer always names its format (GLSL needs layout(format)).
                if (count > 8 && w[3] == kDimBuffer && w[7] == kSampledStorage) ids[w[1]].texel_format = w[8];
                break;
            case kOpTypePointer: {
                Id& id = ids[w[1]];
                id.pointer = true;
                id.storage = w[2];
                id.pointee = w[3];
                break;
            }
            case kOpVariable: {
                Id& id = ids[w[2]];
                id.variable = true;
                id.type = w[1];
                id.storage = w[3];
                break;
            }
            case kOpDecorate: {
                Id& id = ids[w[1]];
                if (w[2] == kDecorationBinding)
                    id.binding = int(w[3]);
                else if (w[2] == kDecorationDescriptorSet)
                    id.set = int(w[3]);
                else if (w[2] == kDecorationNonWritable)
                    id.non_writable = true;
                else if (w[2] == kDecorationNonReadable)
                    id.non_readable = true;
                else if (w[2] == kDecorationBufferBlock)
                    id.buffer_block = true;
                break;
            }
            case kOpMemberDecorate: {
                Id& id = ids[w[1]];
                if (w[3] == kDecorationNonWritable) set_flag(id.member_non_writable, w[2]);
                if (w[3] == kDecorationNonReadable) set_flag(id.member_non_readable, w[2]);
                break;
            }
            default:
                break;
        }
        at += count;
    }
    std::vector<ShaderBinding> out;
    for (const auto& [key, var] : ids) {
        if (!var.variable || var.binding < 0) continue;
        auto pointer = ids.find(var.type);
        if (pointer == ids.end()) continue;
        const Id& block = ids[pointer->second.pointee];
        const bool texel = var.storage == kStorageUniformConstant && block.texel_format != 0;
        if (var.storage != kStorageBuffer && var.storage != kStorageUniform && !texel) continue;
        // Every member NonWritable (or the variable itself) makes the buffer read-only.
        auto all = [&](const std::vector<bool>& flags) {
            if (block.members == 0 || flags.size() < block.members) return false;
            return std::all_of(flags.begin(), flags.begin() + block.members, [](bool b) { return b; });
        };
        ShaderBinding b;
        b.set = uint32_t(var.set);
        b.binding = uint32_t(var.binding);
        b.storage = var.storage == kStorageBuffer || block.buffer_block || texel;
        b.texel_format = texel ? block.texel_format : 0;
        b.writes = b.storage && !(var.non_writable || all(block.member_non_writable));
        b.reads = !(var.non_readable || all(block.member_non_readable));
        if (!var.name.empty())
            b.name = var.name;
        else if (block.member_names.size() == 1 && !block.member_names[0].empty())
            b.name = block.member_names[0];
        else
            b.name = block.name;
        out.push_back(std::move(b));
    }
    std::sort(out.begin(), out.end(), [](const ShaderBinding& a, const ShaderBinding& b) {
        return a.set != b.set ? a.set < b.set : a.binding < b.binding;
    });
    return out;
}

}  // namespace aquaform::gpu
