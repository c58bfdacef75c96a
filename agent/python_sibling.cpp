#include "python_sibling.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "pheromesh/core/python_policy.hpp"

namespace pheromesh::agent {
namespace {

const char* g_sibling = nullptr;
char** g_argv = nullptr;

std::vector<core::PythonPolicyError> exec_sibling(const core::PythonPolicyBlock& /*block*/,
                                                  core::PluginConfig& /*config*/, core::ScenarioConfig& /*cfg*/) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string path = ((ec ? std::filesystem::path(".") : exe.parent_path()) / g_sibling).string();
  spdlog::default_logger()->flush();
  ::execv(path.c_str(), g_argv);
  return {{"", "the policy is written in Python, which this program runs in " + path + ": " + std::strerror(errno) +
                   " (it is installed beside pheromesh-uav when pheromesh is built with Python, docs/python.md)"}};
}

// No Python policy is ever loaded here: the sibling runs them.
const core::PolicyEntry* find_none(std::string_view /*name*/) { return nullptr; }

const core::PythonPolicyHook kHook{.build = &exec_sibling, .find = &find_none};

}  // namespace

void run_python_policies_in(const char* sibling, char** argv) {
  g_sibling = sibling;
  g_argv = argv;
  core::set_python_policy_hook(&kHook);
}

}  // namespace pheromesh::agent
