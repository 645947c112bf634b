// Two plugins of one node, loaded as pluginlib loads them (dlopen, lazy, local symbols): they
// share the node's one core, so a scene one plugin's interface holds cannot be registered again
// by the other's. Usage: test_plugins <plugin_a.so> <plugin_b.so>
#include "../check.hpp"

#include <dlfcn.h>

#include <string>

namespace
{
using Report = bool (*)(cooperation::rtc::Node *, const char *, unsigned char);
using Unload = void (*)();

void * open(const char * path)
{
  void * handle = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
  CHECK(handle != nullptr, std::string("dlopen ") + path + ": " + (handle ? "" : dlerror()));
  return handle;
}

template <class Function>
Function symbol(void * handle, const char * name)
{
  return handle ? reinterpret_cast<Function>(dlsym(handle, name)) : nullptr;
}
}  // namespace

int main(int argc, char ** argv)
{
  if (argc != 3) {
    std::printf("usage: %s <plugin_a.so> <plugin_b.so>\n", argv[0]);
    return 2;
  }
  cooperation::rtc::Node node("behavior_velocity_planner");
  cooperation::rtc::Node other("behavior_path_planner");
  check::Log log(node);
  void * a = open(argv[1]);
  void * b = open(argv[2]);
  auto report_a = symbol<Report>(a, "plugin_report");
  auto report_b = symbol<Report>(b, "plugin_report");
  CHECK(report_a && report_b, "both plugins export plugin_report");
  if (report_a && report_b) {
    CHECK(report_a(&node, "intersection", 7), "plugin A's interface registers scene 7");
    CHECK(!report_b(&node, "crosswalk", 7),
          "plugin B cannot register scene 7 again: one core for the node's plugins");
    CHECK(log.warned("intersection"), "the refusal names the interface that holds the scene");
    CHECK(report_b(&node, "crosswalk", 8), "plugin B's interface registers scene 8");
    CHECK(report_a(&other, "lane_change_left", 7), "another node has a core of its own");
  }
  // The interfaces go before their nodes.
  for (void * handle : {a, b}) {
    if (auto unload = symbol<Unload>(handle, "plugin_unload")) {
      unload();
    }
  }
  return check::report("plugins");
}
