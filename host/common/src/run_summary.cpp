#include "clothlab/host/run_summary.hpp"

#include <set>
#include <type_traits>

#include "clothlab/host/errors.hpp"

namespace clothlab::host {
namespace {

class Writer {
 public:
  explicit Writer(nlohmann::json& out) : out_(out) {}

  template <class T>
  void operator()(const char* name, const T& value) {
    out_[name] = json_of(value);
  }
  template <class T>
  void absent_when_empty(const char* name, const std::optional<T>& value) {
    if (value) out_[name] = json_of(*value);
  }

 private:
  template <class T>
  static nlohmann::json json_of(const T& value) {
    if constexpr (is_optional<T>::value) {
      return value ? json_of(*value) : nlohmann::json(nullptr);
    } else if constexpr (std::is_same_v<T, nlohmann::json> || std::is_arithmetic_v<T> ||
                         std::is_same_v<T, std::string>) {
      return value;  // a double that is not finite dumps as null
    } else {
      nlohmann::json object = nlohmann::json::object();
      Writer writer(object);
      T::fields(value, writer);
      return object;
    }
  }

  nlohmann::json& out_;
};

class Reader {
 public:
  Reader(const nlohmann::json& in, std::string path, std::string_view source)
      : in_(in), path_(std::move(path)), source_(source) {
    if (!in_.is_object()) fail(path_, "expected an object, got " + shown(in_));
  }

  template <class T>
  void operator()(const char* name, T& value) {
    seen_.insert(name);
    const auto found = in_.find(name);
    if (found == in_.end()) fail(field(name), "missing");
    read(*found, field(name), value);
  }
  template <class T>
  void absent_when_empty(const char* name, std::optional<T>& value) {
    seen_.insert(name);
    const auto found = in_.find(name);
    if (found == in_.end()) return;
    read(*found, field(name), value.emplace());
  }

  // After the table: a field it does not name is an error, not ignored.
  void check_every_field_known() const {
    for (const auto& [name, value] : in_.items())
      if (!seen_.count(name)) fail(field(name), "unknown field");
  }

 private:
  std::string field(const std::string& name) const {
    return path_.empty() ? name : path_ + "." + name;
  }

  static std::string shown(const nlohmann::json& value) {
    std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return text.size() > 40 ? text.substr(0, 40) + "..." : text;
  }

  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw InputError(one_line(std::string(source_) + ": run summary" +
                              (field.empty() ? "" : " field '" + field + "'") + ": " + why));
  }

  template <class T>
  void read(const nlohmann::json& json, const std::string& path, T& value) const {
    if constexpr (is_optional<T>::value) {
      if (json.is_null())
        value.reset();
      else
        read(json, path, value.emplace());
    } else if constexpr (std::is_same_v<T, nlohmann::json>) {
      if (!json.is_object()) fail(path, "expected an object, got " + shown(json));
      value = json;
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!json.is_string()) fail(path, "expected text, got " + shown(json));
      value = json.get<std::string>();
    } else if constexpr (std::is_same_v<T, bool>) {
      if (!json.is_boolean()) fail(path, "expected true or false, got " + shown(json));
      value = json.get<bool>();
    } else if constexpr (std::is_floating_point_v<T>) {
      if (json.is_null())
        value = NAN;  // written for a figure that was not finite
      else if (json.is_number())
        value = json.get<T>();
      else
        fail(path, "expected a number, got " + shown(json));
    } else if constexpr (std::is_unsigned_v<T>) {
      if (!json.is_number_unsigned())
        fail(path, "expected a whole number >= 0, got " + shown(json));
      value = json.get<T>();
    } else if constexpr (std::is_integral_v<T>) {
      if (!json.is_number_integer()) fail(path, "expected a whole number, got " + shown(json));
      value = json.get<T>();
    } else {
      Reader reader(json, path, source_);
      T::fields(value, reader);
      reader.check_every_field_known();
    }
  }

  const nlohmann::json& in_;
  std::string path_;
  std::string_view source_;
  std::set<std::string> seen_;
};

}  // namespace

nlohmann::json to_json(const RunSummary& summary) {
  nlohmann::json json = nlohmann::json::object();
  Writer writer(json);
  RunSummary::fields(summary, writer);
  return json;
}

RunSummary run_summary_from_json(const nlohmann::json& json, std::string_view source) {
  RunSummary summary;
  Reader reader(json, "", source);
  RunSummary::fields(summary, reader);
  reader.check_every_field_known();
  return summary;
}

}  // namespace clothlab::host
