// A shared library that is not a policy plugin (no PHEROMESH_POLICY_PLUGIN).
extern "C" __attribute__((visibility("default"))) int not_a_policy() { return 1; }
