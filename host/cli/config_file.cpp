#include "config_file.hpp"

#include <yaml-cpp/yaml.h>

#include <clothlab/host/errors.hpp>
#include <fstream>
#include <map>
#include <sstream>

namespace clothlab::cli {

namespace {

std::string location(const std::string& file, const YAML::Mark& mark) {
  // yaml-cpp counts from 0; editors count from 1.
  return file + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

std::string sequence_text(const YAML::Node& node, const std::string& file, const std::string& key) {
  std::string text = "[";
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    if (!item.IsScalar())
      throw host::InputError(location(file, item.Mark()) + ": " + key +
                             ": a list may hold only plain values; allowed: [x, y, z]");
    if (i > 0) text += ", ";
    text += item.Scalar();
  }
  return text + "]";
}

std::vector<Setting> read_material_file(const std::filesystem::path& path, const std::string& from);

void flatten(const YAML::Node& map, const std::string& prefix, const std::string& file,
             std::vector<Setting>& out) {
  for (const auto& entry : map) {
    const YAML::Node& key_node = entry.first;
    const YAML::Node& value = entry.second;
    if (!key_node.IsScalar() || key_node.Scalar().empty())
      throw host::InputError(location(file, key_node.Mark()) + ": keys must be plain names");
    const std::string key = prefix.empty() ? key_node.Scalar() : prefix + "." + key_node.Scalar();
    switch (value.Type()) {
      case YAML::NodeType::Map:
        flatten(value, key, file, out);
        break;
      case YAML::NodeType::Sequence:
        out.push_back(
            {canonical_key(key), sequence_text(value, file, key), location(file, value.Mark())});
        break;
      case YAML::NodeType::Scalar:
        if (key == "material") {
          // `material: materials/cotton.yaml` takes a preset's material.* values (the path is
          // relative to this file's folder), so presets are written once.
          const std::filesystem::path preset =
              std::filesystem::path(file).parent_path() / value.Scalar();
          const std::vector<Setting> values =
              read_material_file(preset, location(file, value.Mark()));
          out.insert(out.end(), values.begin(), values.end());
          break;
        }
        out.push_back({canonical_key(key), value.Scalar(), location(file, value.Mark())});
        break;
      default:
        throw host::InputError(location(file, key_node.Mark()) + ": " + key +
                               " has no value; allowed: a value, a list or a map");
    }
  }
}

// The same key twice (also spelled differently: a.b and a: {b}) is almost surely a
// mistake, so it is not silently resolved by order.
void reject_repeated_keys(const std::vector<Setting>& settings) {
  std::map<std::string, const Setting*> first;
  for (const Setting& setting : settings) {
    const auto [it, inserted] = first.emplace(setting.key, &setting);
    if (!inserted)
      throw host::InputError(setting.source + ": " + setting.key + " = " + setting.value +
                             " repeats the key already set at " + it->second->source +
                             "; allowed: each key once per file");
  }
}

std::vector<Setting> read_material_file(const std::filesystem::path& path,
                                        const std::string& from) {
  std::vector<Setting> settings;
  try {
    settings = read_config_file(path);
  } catch (const host::InputError& error) {
    throw host::InputError(from + ": material " + path.string() + ": " + error.what());
  }
  for (const Setting& setting : settings)
    if (!setting.key.starts_with("material."))
      throw host::InputError(setting.source + ": " + setting.key +
                             " in a material file; allowed: material.* keys only");
  return settings;
}

}  // namespace

std::vector<Setting> read_config_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream stream(path);
  if (!stream) throw host::InputError(file + ": cannot open config file");
  std::stringstream contents;
  contents << stream.rdbuf();

  YAML::Node root;
  try {
    root = YAML::Load(contents.str());
  } catch (const YAML::ParserException& error) {
    throw host::InputError(location(file, error.mark) + ": YAML syntax error: " + error.msg);
  }
  std::vector<Setting> settings;
  if (root.IsNull()) return settings;
  if (!root.IsMap())
    throw host::InputError(location(file, root.Mark()) +
                           ": expected a map of settings (key: value lines)");
  flatten(root, "", file, settings);
  reject_repeated_keys(settings);
  check_one_length(settings, "config file " + file);
  return settings;
}

}  // namespace clothlab::cli
