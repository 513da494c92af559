#pragma once
// UTF-8 well-formedness (RFC 3629): JSON bodies must be UTF-8 (RFC 8259),
// and a message that quotes a client's bytes must not break the JSON it goes in.
#include <cstddef>
#include <optional>
#include <string_view>

namespace seamap::server {

// The offset of the first byte that is not part of a well-formed UTF-8
// sequence (overlong forms, surrogates and code points past U+10FFFF are
// not), or nullopt when all of `text` is UTF-8.
std::optional<size_t> FirstInvalidUtf8(std::string_view text);

}  // namespace seamap::server
