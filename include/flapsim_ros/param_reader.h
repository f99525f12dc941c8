// Reading a node's parameters from the parameter server's XmlRpc values, with errors that
// name the key: the one reader of the simulator and the controller nodes.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "flapsim/types.h"

namespace flapsim_ros {

/// A missing, mistyped or out-of-range parameter; the message names it.
class ParamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline std::string paramTypeName(const XmlRpc::XmlRpcValue& v) {
  using XmlRpc::XmlRpcValue;
  switch (v.getType()) {
    case XmlRpcValue::TypeBoolean:
      return "a boolean";
    case XmlRpcValue::TypeInt:
      return "an integer";
    case XmlRpcValue::TypeDouble:
      return "a number";
    case XmlRpcValue::TypeString:
      return "a string";
    case XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpcValue::TypeStruct:
      return "a dictionary";
    default:
      return "of an unsupported type";
  }
}

[[noreturn]] inline void failParam(const std::string& key, const std::string& what) {
  throw ParamError("parameter '" + key + "': " + what);
}

/// The members of a parameter struct (a namespace as XmlRpc), read with named errors: a
/// missing key gives the default, a wrong type or a non-finite number throws ParamError
/// naming the key (with the prefix), and the keys never read can be listed or refused.
class ParamReader {
 public:
  using XmlRpcValue = XmlRpc::XmlRpcValue;

  ParamReader(const XmlRpc::XmlRpcValue& v, std::string prefix)
      : v_(v), prefix_(std::move(prefix)) {
    if (v_.getType() != XmlRpcValue::TypeStruct) {
      failParam(prefix_.empty() ? "~" : prefix_, "must be a dictionary, got " + paramTypeName(v_));
    }
  }

  std::string key(const std::string& k) const { return prefix_.empty() ? k : prefix_ + "/" + k; }
  const std::string& name() const { return prefix_; }
  bool has(const std::string& k) const { return v_.hasMember(k); }
  const XmlRpcValue& at(const std::string& k) const {
    read_.insert(k);
    return const_cast<XmlRpcValue&>(v_)[k];
  }

  double number(const std::string& k, double def) const {
    if (!has(k)) return def;
    return toNumber(at(k), key(k));
  }
  bool boolean(const std::string& k, bool def) const {
    if (!has(k)) return def;
    const XmlRpcValue& x = at(k);
    if (x.getType() != XmlRpcValue::TypeBoolean)
      failParam(key(k), "must be true or false, got " + paramTypeName(x));
    return static_cast<bool>(const_cast<XmlRpcValue&>(x));
  }
  int integer(const std::string& k, int def) const {
    if (!has(k)) return def;
    const XmlRpcValue& x = at(k);
    if (x.getType() != XmlRpcValue::TypeInt)
      failParam(key(k), "must be an integer, got " + paramTypeName(x));
    return static_cast<int>(const_cast<XmlRpcValue&>(x));
  }
  std::string string(const std::string& k, const std::string& def) const {
    if (!has(k)) return def;
    const XmlRpcValue& x = at(k);
    if (x.getType() != XmlRpcValue::TypeString)
      failParam(key(k), "must be a string, got " + paramTypeName(x));
    return static_cast<std::string>(const_cast<XmlRpcValue&>(x));
  }
  std::vector<double> numbers(const std::string& k) const {
    const XmlRpcValue& x = at(k);
    if (x.getType() != XmlRpcValue::TypeArray)
      failParam(key(k), "must be a list of numbers, got " + paramTypeName(x));
    std::vector<double> out;
    for (int i = 0; i < x.size(); ++i) {
      out.push_back(
          toNumber(const_cast<XmlRpcValue&>(x)[i], key(k) + "[" + std::to_string(i) + "]"));
    }
    return out;
  }
  std::vector<std::string> strings(const std::string& k) const {
    const XmlRpcValue& x = at(k);
    if (x.getType() != XmlRpcValue::TypeArray)
      failParam(key(k), "must be a list of strings, got " + paramTypeName(x));
    std::vector<std::string> out;
    for (int i = 0; i < x.size(); ++i) {
      XmlRpcValue& e = const_cast<XmlRpcValue&>(x)[i];
      if (e.getType() != XmlRpcValue::TypeString) {
        failParam(key(k) + "[" + std::to_string(i) + "]",
                  "must be a string, got " + paramTypeName(e));
      }
      out.push_back(static_cast<std::string>(e));
    }
    return out;
  }
  flapsim::Vec3 vec3(const std::string& k, const flapsim::Vec3& def) const {
    if (!has(k)) return def;
    std::vector<double> v = numbers(k);
    if (v.size() != 3) failParam(key(k), "must have 3 numbers, got " + std::to_string(v.size()));
    return flapsim::Vec3(v[0], v[1], v[2]);
  }

  /// Throws for members that were never read.
  void rejectUnknown() const {
    for (const std::string& k : unknownKeys()) failParam(key(k), "unknown parameter (misspelt?)");
  }
  std::vector<std::string> unknownKeys() const {
    std::vector<std::string> out;
    for (auto it = const_cast<XmlRpcValue&>(v_).begin(); it != const_cast<XmlRpcValue&>(v_).end();
         ++it) {
      if (!read_.count(it->first)) out.push_back(it->first);
    }
    return out;
  }

  static double toNumber(const XmlRpcValue& x, const std::string& key) {
    double d = 0.0;
    if (x.getType() == XmlRpcValue::TypeDouble) {
      d = static_cast<double>(const_cast<XmlRpcValue&>(x));
    } else if (x.getType() == XmlRpcValue::TypeInt) {
      d = static_cast<int>(const_cast<XmlRpcValue&>(x));
    } else {
      failParam(key, "must be a number, got " + paramTypeName(x));
    }
    if (!std::isfinite(d)) failParam(key, "must be finite");
    return d;
  }

 private:
  const XmlRpcValue& v_;
  std::string prefix_;
  mutable std::set<std::string> read_;
};

}  // namespace flapsim_ros
