#include "clothlab/config/yaml_settings.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/eventhandler.h>

#include <cerrno>
#include <clothlab/host/errors.hpp>
#include <cstring>
#include <map>
#include <sstream>

namespace clothlab::config {

namespace {

constexpr size_t max_file_bytes = 1 << 20;
constexpr size_t max_values = 100000;
constexpr int max_depth = 32;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw host::InputError(where + ": " + what);
}

std::string read_bounded(const std::filesystem::path& path) {
  const std::string file = path.string();
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail(file, std::string("cannot open config file: ") + std::strerror(errno));
  struct stat status {};
  const auto refuse = [&](const std::string& what) {
    ::close(fd);
    fail(file, what);
  };
  if (::fstat(fd, &status) != 0) refuse(std::strerror(errno));
  if (S_ISDIR(status.st_mode)) refuse("is a folder; allowed: a YAML file");
  if (!S_ISREG(status.st_mode))
    refuse("is not a regular file (a FIFO or device); allowed: a YAML file");
  if (static_cast<size_t>(status.st_size) > max_file_bytes)
    refuse(std::to_string(status.st_size) + " bytes; allowed: at most 1 MiB");
  std::string text(max_file_bytes + 1, '\0');
  size_t used = 0;
  while (used < text.size()) {
    const ssize_t n = ::read(fd, text.data() + used, text.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse(std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) break;
    used += static_cast<size_t>(n);
  }
  ::close(fd);
  if (used > max_file_bytes) fail(file, "more than 1 MiB; allowed: at most 1 MiB");
  text.resize(used);
  return text;
}

class Flattener {
 public:
  Flattener(const std::string& source, std::vector<Setting>& out) : source_(source), out_(out) {}

  void map(const YAML::Node& node, const std::string& prefix, int depth) {
    if (depth > max_depth)
      fail(location(source_, node.Mark()), prefix + ": nested deeper than 32 maps");
    for (const auto& entry : node) {
      const std::string name = key_text(entry.first, source_);
      const std::string key = prefix.empty() ? name : prefix + "." + name;
      const YAML::Node& value = entry.second;
      count(value);
      const std::string where = location(source_, value.Mark());
      switch (value.Type()) {
        case YAML::NodeType::Map:
          if (value.size() == 0)
            fail(where, key +
                            " = {}: an empty map sets nothing; allowed: a value, a list or "
                            "a map of settings");
          map(value, key, depth + 1);
          break;
        case YAML::NodeType::Sequence:
          out_.push_back({canonical_key(key), sequence_text(value, key), where});
          break;
        case YAML::NodeType::Scalar:
          if (key == "material") {
            include_material(value.Scalar(), where);
            break;
          }
          out_.push_back({canonical_key(key), value.Scalar(), where});
          break;
        default:
          fail(location(source_, entry.first.Mark()),
               key + " has no value; allowed: a value, a list or a map");
      }
    }
  }

 private:
  // `material: materials/cotton.yaml` takes a preset's material.* values (the path is
  // relative to this file's folder), so presets are written once.
  void include_material(const std::string& relative, const std::string& where) {
    const std::filesystem::path preset = std::filesystem::path(source_).parent_path() / relative;
    std::vector<Setting> settings;
    try {
      settings = read_config_file(preset);
    } catch (const host::InputError& error) {
      throw host::InputError(where + ": material " + preset.string() + ": " + error.what());
    }
    for (const Setting& setting : settings)
      if (!setting.key.starts_with("material."))
        fail(setting.source, setting.key + " in a material file; allowed: material.* keys only");
    out_.insert(out_.end(), settings.begin(), settings.end());
  }

  void count(const YAML::Node& node) {
    if (++values_ > max_values)
      fail(location(source_, node.Mark()),
           "more than 100000 values (aliases expanded); allowed: at most 100000");
  }

  std::string sequence_text(const YAML::Node& node, const std::string& key) {
    std::string text = "[";
    for (size_t i = 0; i < node.size(); ++i) {
      const YAML::Node item = node[i];
      count(item);
      if (!item.IsScalar())
        fail(location(source_, item.Mark()),
             key + ": a list may hold only plain values; allowed: [x, y, z]");
      if (i > 0) text += ", ";
      text += item.Scalar();
    }
    return text + "]";
  }

  const std::string& source_;
  std::vector<Setting>& out_;
  size_t values_ = 0;
};

// Records where each document starts; the nodes themselves are built by YAML::Load.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> marks;

  void OnDocumentStart(const YAML::Mark& mark) override { marks.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// Whether text holds a document (a blank or comment-only file holds none); throws for a
// second one. Parses at most two: yaml-cpp reads a ',' outside a [list] or {map} as an empty
// document without consuming it, so reading documents to the end (YAML::LoadAll) never ends
// and keeps allocating nodes.
bool has_one_document(const std::string& text, const std::string& source) {
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  DocumentStarts starts;
  while (starts.marks.size() < 2 && parser.HandleNextDocument(starts)) {
    const YAML::Mark& start = starts.marks.back();
    if (start.pos >= 0 && static_cast<size_t>(start.pos) < text.size() && text[start.pos] == ',')
      fail(location(source, start),
           "YAML syntax error: ',' outside a [list] or {map}; allowed: key: value lines");
  }
  if (starts.marks.size() > 1)
    fail(location(source, starts.marks[1]),
         "a second YAML document; allowed: one document per file");
  return !starts.marks.empty();
}

std::string document_kind(const YAML::Node& root) {
  if (root.IsSequence()) return "a list";
  if (root.IsScalar()) return "the value '" + root.Scalar() + "'";
  return "empty or null (`---`, `~`, an anchor or a tag alone)";
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

}  // namespace

std::string location(const std::string& source, const YAML::Mark& mark) {
  if (mark.line < 0) return source;
  // yaml-cpp counts from 0; editors count from 1.
  return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

std::string key_text(const YAML::Node& key, const std::string& source) {
  if (!key.IsScalar() || key.Scalar().empty())
    fail(location(source, key.Mark()), "keys must be plain names; allowed: name: value");
  return key.Scalar();
}

YAML::Node load_yaml_text(const std::string& text, const std::string& source) {
  try {
    return has_one_document(text, source) ? YAML::Load(text) : YAML::Node();
  } catch (const YAML::Exception& error) {
    fail(location(source, error.mark), "YAML syntax error: " + error.msg);
  }
}

YAML::Node load_yaml_file(const std::filesystem::path& path) {
  return load_yaml_text(read_bounded(path), path.string());
}

std::vector<Setting> flatten_settings(const YAML::Node& root, const std::string& source) {
  std::vector<Setting> settings;
  // No document at all (a blank or comment-only file) has no position and sets nothing; an
  // empty or null document (`---`, `~`, `&a`, `!`) is refused with the other non-maps.
  if (root.IsNull() && root.Mark().line < 0) return settings;
  if (!root.IsMap())
    fail(location(source, root.Mark()), "the document is " + document_kind(root) +
                                            "; allowed: a map of settings (key: value lines)");
  Flattener(source, settings).map(root, "", 0);
  reject_repeated_keys(settings);
  return settings;
}

std::vector<Setting> read_config_file(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::vector<Setting> settings = flatten_settings(load_yaml_file(path), file);
  check_one_length(settings, "config file " + file);
  return settings;
}

}  // namespace clothlab::config
