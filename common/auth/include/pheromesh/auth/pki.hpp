// The public-key material of a DDS Security swarm (docs/security.md), made
// with OpenSSL's C API: a CA, an identity certificate per process, and the
// S/MIME signatures of the governance and permissions documents that both
// vendors' builtin plugins verify against the CA. Keys are ECDSA P-256: a
// PKI-DH handshake signs and verifies with them, and P-256 is several times
// cheaper than RSA-2048 on a host that runs a whole swarm.
#pragma once

#include <chrono>
#include <string>

#include "pheromesh/core/result.hpp"

namespace pheromesh::auth {

// A certificate and its private key, both PEM.
struct KeyPair {
  std::string cert;
  std::string key;
};

struct Validity {
  std::chrono::system_clock::time_point not_before;
  std::chrono::system_clock::time_point not_after;
};
// From an hour ago (clocks of a LAN differ a little) to `days` from now.
Validity validity_from_now(uint32_t days);
// "YYYY-MM-DDThh:mm:ss" in UTC, the permissions document's date format.
std::string permissions_date(std::chrono::system_clock::time_point t);

// A new key and a self-signed CA certificate with subject CN=`common_name`.
core::Result<KeyPair> make_ca(const std::string& common_name, const Validity& v);
// A new key and a certificate for CN=`common_name` signed by `ca`.
core::Result<KeyPair> make_identity(const KeyPair& ca, const std::string& common_name, const Validity& v);
// `document` signed by `ca` as S/MIME (multipart/signed, text/plain content),
// as `openssl smime -sign -text` writes it.
core::Result<std::string> smime_sign(const KeyPair& ca, const std::string& document);
// True if `smime` is a valid signature by `ca_cert` of a document; the
// document in `content` (for tests and `security init`'s own check).
bool smime_verify(const std::string& ca_cert, const std::string& smime, std::string* content = nullptr);

}  // namespace pheromesh::auth
