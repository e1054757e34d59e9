#include "host/scene/json_reader.h"

#include <cmath>
#include <sstream>

#include "host/core/error.h"
#include "host/core/input_file.h"

namespace cutwork {

std::string format_number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream ss;
  ss.precision(10);
  ss << v;
  return ss.str();
}

namespace {
std::string type_name(const nlohmann::json& v) { return v.type_name(); }

std::string range_text(double lo, double hi, bool lo_open, bool hi_open) {
  if (std::isinf(hi) && std::isinf(lo)) return "any finite number";
  if (std::isinf(hi)) return std::string(lo_open ? "> " : ">= ") + format_number(lo);
  if (std::isinf(lo)) return std::string(hi_open ? "< " : "<= ") + format_number(hi);
  return std::string(lo_open ? "in (" : "in [") + format_number(lo) + ", " + format_number(hi) +
         (hi_open ? ")" : "]");
}
}  // namespace

Vec3 json_to_vec3(const nlohmann::json& value, const std::string& origin, const std::string& path) {
  if (!value.is_array() || value.size() != 3)
    throw InputError(origin + ": " + path + ": expected an array of 3 numbers (got " +
                     (value.is_array() ? std::to_string(value.size()) + " entries" : type_name(value)) +
                     ")");
  Vec3 out;
  for (int k = 0; k < 3; ++k) {
    if (!value[k].is_number())
      throw InputError(origin + ": " + path + "/" + std::to_string(k) + ": expected a number (got " +
                       type_name(value[k]) + ")");
    out[k] = value[k].get<double>();
    if (!std::isfinite(out[k]))
      throw InputError(origin + ": " + path + "/" + std::to_string(k) + ": must be finite");
  }
  return out;
}

JsonObjectReader::JsonObjectReader(const nlohmann::json& object, std::string origin, std::string path)
    : m_object(object), m_origin(std::move(origin)), m_path(std::move(path)) {
  if (!m_object.is_object())
    throw InputError(m_origin + ": " + (m_path.empty() ? "/" : m_path) + ": expected an object (got " +
                     type_name(m_object) + ")");
}

bool JsonObjectReader::has(const std::string& key) const { return m_object.contains(key); }

std::string JsonObjectReader::path_of(const std::string& key) const { return m_path + "/" + key; }

void JsonObjectReader::fail(const std::string& key, const std::string& problem) const {
  throw InputError(m_origin + ": " + (key.empty() ? (m_path.empty() ? "/" : m_path) : path_of(key)) +
                   ": " + problem);
}

const nlohmann::json* JsonObjectReader::child(const std::string& key) {
  m_accepted.insert(key);
  auto it = m_object.find(key);
  if (it == m_object.end()) return nullptr;
  m_read.insert(key);
  return &*it;
}

double JsonObjectReader::number(const std::string& key, double fallback, double lo, double hi,
                                bool lo_open, bool hi_open) {
  const nlohmann::json* v = child(key);
  if (!v) return fallback;
  if (!v->is_number())
    fail(key, "expected a number, " + range_text(lo, hi, lo_open, hi_open) + " (got " + type_name(*v) + ")");
  const double x = v->get<double>();
  const bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  if (!ok) fail(key, "must be " + range_text(lo, hi, lo_open, hi_open) + " (got " + format_number(x) + ")");
  return x;
}

double JsonObjectReader::required_number(const std::string& key, double lo, double hi, bool lo_open,
                                         bool hi_open) {
  if (!has(key)) {
    m_accepted.insert(key);
    fail(key, "is required: a number, " + range_text(lo, hi, lo_open, hi_open));
  }
  return number(key, 0, lo, hi, lo_open, hi_open);
}

int JsonObjectReader::integer(const std::string& key, int fallback, int lo, int hi) {
  const nlohmann::json* v = child(key);
  if (!v) return fallback;
  const std::string range = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!v->is_number_integer() && !(v->is_number() && std::floor(v->get<double>()) == v->get<double>()))
    fail(key, "expected " + range + " (got " + (v->is_number() ? format_number(v->get<double>()) : type_name(*v)) + ")");
  const double x = v->get<double>();
  if (x < lo || x > hi) fail(key, "must be " + range + " (got " + format_number(x) + ")");
  return int(x);
}

bool JsonObjectReader::boolean(const std::string& key, bool fallback) {
  const nlohmann::json* v = child(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "expected true or false (got " + type_name(*v) + ")");
  return v->get<bool>();
}

std::string JsonObjectReader::string(const std::string& key, const std::string& fallback,
                                     const std::vector<std::string>& allowed) {
  const nlohmann::json* v = child(key);
  if (!v) return fallback;
  if (!v->is_string()) fail(key, "expected a string (got " + type_name(*v) + ")");
  std::string s = v->get<std::string>();
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "unknown value '" + excerpt(s) + "' (accepted: " + list + ")");
  }
  return s;
}

std::string JsonObjectReader::required_string(const std::string& key,
                                              const std::vector<std::string>& allowed) {
  if (!has(key)) {
    m_accepted.insert(key);
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "is required" + (list.empty() ? std::string() : " (one of: " + list + ")"));
  }
  return string(key, "", allowed);
}

Vec3 JsonObjectReader::vec3(const std::string& key, const Vec3& fallback) {
  const nlohmann::json* v = child(key);
  if (!v) return fallback;
  return json_to_vec3(*v, m_origin, path_of(key));
}

Vec3 JsonObjectReader::required_vec3(const std::string& key) {
  if (!has(key)) {
    m_accepted.insert(key);
    fail(key, "is required: an array of 3 numbers");
  }
  return vec3(key, Vec3::Zero());
}

const nlohmann::json& JsonObjectReader::array(const std::string& key) {
  static const nlohmann::json empty = nlohmann::json::array();
  const nlohmann::json* v = child(key);
  if (!v) return empty;
  if (!v->is_array()) fail(key, "expected an array (got " + type_name(*v) + ")");
  return *v;
}

JsonObjectReader JsonObjectReader::object(const std::string& key) {
  static const nlohmann::json empty = nlohmann::json::object();
  const nlohmann::json* v = child(key);
  return JsonObjectReader(v ? *v : empty, m_origin, path_of(key));
}

void JsonObjectReader::finish() const {
  for (auto it = m_object.begin(); it != m_object.end(); ++it) {
    if (m_read.count(it.key())) continue;
    std::string list;
    for (const auto& a : m_accepted) list += (list.empty() ? "" : ", ") + a;
    throw InputError(m_origin + ": " + path_of(excerpt(it.key())) + ": unknown key (accepted here: " +
                     (list.empty() ? std::string("none") : list) + ")");
  }
}

}  // namespace cutwork
