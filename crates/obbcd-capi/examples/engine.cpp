// obbcd's C ABI from C++: an owning wrapper (the engine freed by its destructor, a failed call
// thrown as an exception with obbcd's reason) and a short run: a tissue strip (group 0, kept
// resident) and a probe box (group 1) that moves along it. Prints each frame's pairs.
//
// Build (from the workspace, after `cargo build --release -p obbcd-capi`):
//   c++ -std=c++17 -O2 -I crates/obbcd-capi/include crates/obbcd-capi/examples/engine.cpp
//       target/release/libobbcd_c.a -lpthread -ldl -lm -o engine
#include "obbcd.h"

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

namespace obbcd {

// Throws obbcd's reason for a failed call.
inline void check(ObbcdStatus status) {
  if (status != OBBCD_STATUS_OK) throw std::runtime_error(obbcd_last_error());
}

class Engine {
 public:
  Engine(const char *group_mask, const std::vector<uint32_t> &static_groups, uint32_t threads) {
    ObbcdEngine *e = nullptr;
    check(obbcd_engine_new(group_mask, static_groups.data(), static_groups.size(), threads, &e));
    engine_.reset(e);
  }

  void set_boxes(uint32_t group, const std::vector<ObbcdBox> &boxes) {
    check(obbcd_set_boxes(engine_.get(), group, boxes.data(), boxes.size()));
  }

  // The pairs stay valid until the next set_boxes or detect: copy them to keep them.
  std::pair<const ObbcdPair *, size_t> detect() {
    check(obbcd_detect(engine_.get(), nullptr));
    const ObbcdPair *pairs = nullptr;
    size_t n = 0;
    check(obbcd_pairs(engine_.get(), &pairs, &n));
    return {pairs, n};
  }

  std::pair<const ObbcdContact *, size_t> contacts() {
    const ObbcdContact *contacts = nullptr;
    size_t n = 0;
    check(obbcd_contacts(engine_.get(), &contacts, &n));
    return {contacts, n};
  }

 private:
  struct Free {
    void operator()(ObbcdEngine *e) const { obbcd_engine_free(e); }
  };
  std::unique_ptr<ObbcdEngine, Free> engine_;
};

}  // namespace obbcd

// An axis-aligned box.
static ObbcdBox aligned(double x, double y, double z, double hx, double hy, double hz) {
  return ObbcdBox{{x, y, z}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {hx, hy, hz}};
}

int main() {
  try {
    obbcd::Engine engine("cross", {0}, 1);
    std::vector<ObbcdBox> strip;
    for (int i = 0; i < 10; i++) strip.push_back(aligned(i + 0.5, 0.5, 0.0, 0.5, 0.5, 0.1));
    engine.set_boxes(0, strip);
    for (int k = 0; k < 5; k++) {
      // The probe: 0.6 mm wide, its bottom 0.05 mm into the strip, 2 mm further each frame.
      engine.set_boxes(1, {aligned(1.0 + 2 * k, 0.5, 0.35, 0.3, 0.3, 0.3)});
      auto [pairs, n] = engine.detect();
      auto [contacts, m] = engine.contacts();
      std::printf("frame %d:", k);
      for (size_t p = 0; p < n && p < m; p++)
        std::printf(" %u.%u-%u.%u depth %.3f", pairs[p].group_a, pairs[p].index_a,
                    pairs[p].group_b, pairs[p].index_b, contacts[p].depth);
      std::printf("\n");
    }
    // A box with a negative half-length: the wrapper throws obbcd's reason.
    engine.set_boxes(1, {aligned(0, 0, 0, -1, 1, 1)});
  } catch (const std::exception &e) {
    std::printf("error: %s\n", e.what());
    return 0;
  }
  return 1;
}
