// YAML as the parameter server holds it (rosparam's typing rules), for the tests of node
// parameters without a master.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace flapsim_test {

// YAML as the parameter server would hold it (rosparam's typing rules).
inline XmlRpc::XmlRpcValue toXmlRpc(const YAML::Node& n) {
  XmlRpc::XmlRpcValue v;
  if (n.IsMap()) {
    v.begin();  // make it a struct even if empty
    for (const auto& kv : n) v[kv.first.as<std::string>()] = toXmlRpc(kv.second);
  } else if (n.IsSequence()) {
    v.setSize(static_cast<int>(n.size()));
    for (size_t i = 0; i < n.size(); ++i) v[static_cast<int>(i)] = toXmlRpc(n[i]);
  } else if (n.IsScalar()) {
    const std::string s = n.Scalar();
    bool b;
    int i;
    double d;
    if (n.Tag() == "!") {
      v = s;  // quoted: a string
    } else if (YAML::convert<bool>::decode(n, b) && (s == "true" || s == "false")) {
      v = b;
    } else if (YAML::convert<int>::decode(n, i)) {
      v = i;
    } else if (YAML::convert<double>::decode(n, d)) {
      v = d;
    } else {
      v = s;
    }
  }
  return v;
}

}  // namespace flapsim_test
