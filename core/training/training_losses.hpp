#pragma once
// Training never hides losses (issue 12): every mesh that was refused (validation, off-recipe map) or failed (map,
// fit) is counted per class and per error code, shown in the training report and on stdout, and training stops
// with a clear error when any class loses more than a configured share of its meshes — a class that lost 18 of 20
// members must not be shown as trained.

#include <map>
#include <string>
#include <vector>

namespace wish {

// One mesh that did not become a training sample.
struct MeshLoss {
  std::string id;       // file
  std::string label;    // its class
  std::string code;     // WishError code: "degenerate_faces", "map_failed", "off_recipe", "timeout", ...
  std::string message;
};

struct ClassLosses {
  std::string label;
  int total = 0;    // meshes given for the class
  int kept = 0;     // training samples
  int flagged = 0;  // kept, but from an off-recipe map accepted by the policy (accept_flagged)
  std::map<std::string, int> lost_by_code;
  int lost() const { return total - kept; }
  double lost_share() const { return total > 0 ? static_cast<double>(lost()) / total : 0.0; }
};

struct LossPolicy {
  double max_class_loss = 0.1;  // largest share of a class's meshes that may be lost
  bool allow_losses = false;    // true: report, never stop
};

// One row per class (sorted by label) of the kept samples' labels, the losses and the flagged samples' labels.
std::vector<ClassLosses> summarize_losses(const std::vector<std::string>& kept_labels,
                                          const std::vector<MeshLoss>& losses,
                                          const std::vector<std::string>& flagged_labels);

// Throws InvalidInputError("training_losses") naming every class over the limit, with its counts and codes,
// unless policy.allow_losses.
void enforce_loss_policy(const std::vector<ClassLosses>& classes, const LossPolicy& policy);

// "class  meshes  kept  lost  share  flagged  reasons" table; reasons as "code xN, ...".
std::string loss_table(const std::vector<ClassLosses>& classes);

}  // namespace wish
