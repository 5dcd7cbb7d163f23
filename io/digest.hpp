#pragma once
/// Checksums of input files for provenance (OpenSSL's SHA-256).
#include <string>

namespace em {

/// SHA-256 of `bytes` as 64 lowercase hex digits (what `sha256sum` prints).
std::string sha256Hex(const std::string& bytes);

}  // namespace em
