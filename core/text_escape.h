// What a user gives (a scene's name, a file's path, a mesh's or a method's name) written into the
// formats aquaform writes, one helper a format: whatever the bytes, the file stays well-formed
// (JSON that parses, XML that a parser accepts; CSV fields: core/csv.h).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace aquaform {

/// `text` as valid UTF-8: each byte that starts no valid sequence becomes U+FFFD.
std::string valid_utf8(std::string_view text);

/// `doc` as JSON text (`indent` as nlohmann's dump); strings that are not UTF-8 (a file name in
/// another encoding) have their bad bytes replaced by U+FFFD instead of throwing.
std::string json_text(const nlohmann::json& doc, int indent = -1);
/// json_text and a line break into `path`, whole or not at all (core/file_write.h).
Result<bool> write_json_file(const std::filesystem::path& path, const nlohmann::json& doc, int indent = 2);

/// Text for XML content or an attribute value: & < > " ' escaped, characters XML 1.0 does not
/// allow (control characters other than tab and line breaks) and bad UTF-8 become U+FFFD.
std::string xml_text(std::string_view text);

}  // namespace aquaform
