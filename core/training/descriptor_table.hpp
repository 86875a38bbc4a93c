#pragma once
// Labelled descriptor tables on disk, so a grid search need not redo the flows (issue 5): reads the CSV of
// `wish describe --csv` (columns file, ..., xi_0..xi_L) plus, when present, a `label` column and global
// descriptor columns g_<name> (as written by `wish train --save-descriptors`); labels may instead come from a
// separate manifest (path,label) joined on the file column (exact path, else file name). Other columns are
// ignored; a non-empty label_id column (an object of a label volume) makes the sample's id "<file>#<label_id>",
// as `wish train` names volume objects. RFC 4180 quoting.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/training/training.hpp"

namespace wish {

std::vector<std::vector<std::string>> parse_csv(const std::string& text);

struct DescriptorTable {
  std::vector<TrainingSample> samples;
  int lmax = -1;              // highest xi column
  bool has_global = false;    // all g_<name> columns present
  std::vector<std::string> unlabelled;  // files without a label (skipped, reported)
};

// `labels`: file -> label from a manifest; may be empty when the CSV has a label column.
// Throws InvalidInputError("invalid_descriptor_csv") with the line number on malformed content.
DescriptorTable read_descriptor_table(const std::string& csv_text, const std::map<std::string, std::string>& labels = {});
// Every row, labelled or not (label empty when there is none): the input of `wish predict --descriptors`.
DescriptorTable read_unlabelled_descriptor_table(const std::string& csv_text);
// Reads a manifest CSV "path,label" (header optional); relative paths are resolved against `base`.
std::vector<std::pair<std::string, std::string>> read_manifest(const std::string& csv_text, const std::filesystem::path& base);
std::string write_descriptor_table(const std::vector<TrainingSample>& samples);

}  // namespace wish
