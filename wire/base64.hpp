#pragma once
// Base64 (RFC 4648 §4, with padding): how binary results travel inside JSON, e.g. the class map of a classified
// label volume (`?output=labels`, VolumeResult.class_map.data).

#include <string>
#include <string_view>

namespace wish::wire {

std::string base64_encode(std::string_view bytes);

}  // namespace wish::wire
