#pragma once
// Per-class spectra of a training set (ClassSpectrum, classifier_model.hpp): mean and standard deviation of
// ln xi(l), l = 1..Lmax, over each class's samples. Stored in the model file so that a client can draw a new
// shape's spectrum against the classes it is judged by (the web page's spectrum plot, issue 14).

#include <string>
#include <vector>

#include "core/classify/classifier_model.hpp"
#include "core/training/training.hpp"

namespace wish {

// One entry per name in `classes`, in that order. Samples of other labels are ignored. The length is the shortest
// invariants vector of the class minus xi(0); a class without samples gets count 0 and empty vectors.
std::vector<ClassSpectrum> class_spectra(const std::vector<TrainingSample>& samples, const std::vector<std::string>& classes);

}  // namespace wish
