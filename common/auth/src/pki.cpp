#include "pheromesh/auth/pki.hpp"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <ctime>
#include <memory>

namespace pheromesh::auth {
namespace {

template <auto Free>
struct Deleter {
  template <typename T>
  void operator()(T* p) const {
    Free(p);
  }
};
using PkeyPtr = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY_free>>;
using X509Ptr = std::unique_ptr<X509, Deleter<X509_free>>;
using BioPtr = std::unique_ptr<BIO, Deleter<BIO_free_all>>;
using Pkcs7Ptr = std::unique_ptr<PKCS7, Deleter<PKCS7_free>>;
using StorePtr = std::unique_ptr<X509_STORE, Deleter<X509_STORE_free>>;

// OpenSSL's last error, for messages.
core::Error ssl_error(const std::string& what) {
  std::string msg = what;
  const unsigned long e = ERR_get_error();
  if (e != 0) {
    char buf[256];
    ERR_error_string_n(e, buf, sizeof buf);
    msg += ": ";
    msg += buf;
  }
  ERR_clear_error();
  return core::Error{msg};
}

BioPtr mem_bio(const std::string& s) { return BioPtr(BIO_new_mem_buf(s.data(), static_cast<int>(s.size()))); }

std::string bio_string(BIO* b) {
  char* data = nullptr;
  const long n = BIO_get_mem_data(b, &data);
  return n > 0 ? std::string(data, static_cast<std::size_t>(n)) : std::string();
}

PkeyPtr new_p256_key() { return PkeyPtr(EVP_EC_gen("P-256")); }

std::string key_pem(EVP_PKEY* k) {
  BioPtr b(BIO_new(BIO_s_mem()));
  if (PEM_write_bio_PrivateKey(b.get(), k, nullptr, nullptr, 0, nullptr, nullptr) != 1) return {};
  return bio_string(b.get());
}

std::string cert_pem(X509* c) {
  BioPtr b(BIO_new(BIO_s_mem()));
  if (PEM_write_bio_X509(b.get(), c) != 1) return {};
  return bio_string(b.get());
}

PkeyPtr read_key(const std::string& pem) {
  BioPtr b = mem_bio(pem);
  return PkeyPtr(PEM_read_bio_PrivateKey(b.get(), nullptr, nullptr, nullptr));
}

X509Ptr read_cert(const std::string& pem) {
  BioPtr b = mem_bio(pem);
  return X509Ptr(PEM_read_bio_X509(b.get(), nullptr, nullptr, nullptr));
}

bool add_ext(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value);
  if (ext == nullptr) return false;
  const bool ok = X509_add_ext(cert, ext, -1) == 1;
  X509_EXTENSION_free(ext);
  return ok;
}

// A certificate for `key` with subject CN=`cn`, issued by `issuer` (itself if
// null) and signed with `issuer_key`.
core::Result<X509Ptr> make_cert(EVP_PKEY* key, const std::string& cn, X509* issuer, EVP_PKEY* issuer_key,
                                const Validity& v, bool ca) {
  X509Ptr cert(X509_new());
  if (!cert) return ssl_error("X509_new");
  X509_set_version(cert.get(), 2);  // v3
  // A random 120-bit serial: unique per certificate without a serial file.
  unsigned char serial[15];
  if (RAND_bytes(serial, sizeof serial) != 1) return ssl_error("RAND_bytes");
  serial[0] &= 0x7F;  // positive
  BIGNUM* bn = BN_bin2bn(serial, sizeof serial, nullptr);
  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert.get()));
  BN_free(bn);
  ASN1_TIME_set(X509_getm_notBefore(cert.get()), std::chrono::system_clock::to_time_t(v.not_before));
  ASN1_TIME_set(X509_getm_notAfter(cert.get()), std::chrono::system_clock::to_time_t(v.not_after));
  X509_NAME* name = X509_get_subject_name(cert.get());
  if (X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_UTF8, reinterpret_cast<const unsigned char*>(cn.c_str()), -1, -1,
                                 0) != 1) {
    return ssl_error("subject CN=" + cn);
  }
  X509_set_issuer_name(cert.get(), issuer != nullptr ? X509_get_subject_name(issuer) : name);
  X509_set_pubkey(cert.get(), key);
  X509* iss = issuer != nullptr ? issuer : cert.get();
  const bool ext_ok = ca ? add_ext(cert.get(), iss, NID_basic_constraints, "critical,CA:TRUE") &&
                               add_ext(cert.get(), iss, NID_key_usage, "critical,keyCertSign,cRLSign,digitalSignature") &&
                               add_ext(cert.get(), iss, NID_subject_key_identifier, "hash")
                         : add_ext(cert.get(), iss, NID_basic_constraints, "critical,CA:FALSE") &&
                               add_ext(cert.get(), iss, NID_key_usage, "critical,digitalSignature,keyAgreement") &&
                               add_ext(cert.get(), iss, NID_subject_key_identifier, "hash") &&
                               add_ext(cert.get(), iss, NID_authority_key_identifier, "keyid:always");
  if (!ext_ok) return ssl_error("certificate extensions of CN=" + cn);
  if (X509_sign(cert.get(), issuer_key, EVP_sha256()) == 0) return ssl_error("signing the certificate of CN=" + cn);
  return cert;
}

}  // namespace

Validity validity_from_now(uint32_t days) {
  const auto now = std::chrono::system_clock::now();
  return {now - std::chrono::hours(1), now + std::chrono::hours(24) * days};
}

std::string permissions_date(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

core::Result<KeyPair> make_ca(const std::string& common_name, const Validity& v) {
  PkeyPtr key = new_p256_key();
  if (!key) return ssl_error("generating a P-256 key");
  auto cert = make_cert(key.get(), common_name, nullptr, key.get(), v, true);
  if (!cert) return cert.error();
  return KeyPair{cert_pem(cert->get()), key_pem(key.get())};
}

core::Result<KeyPair> make_identity(const KeyPair& ca, const std::string& common_name, const Validity& v) {
  X509Ptr ca_cert = read_cert(ca.cert);
  PkeyPtr ca_key = read_key(ca.key);
  if (!ca_cert || !ca_key) return ssl_error("reading the CA");
  PkeyPtr key = new_p256_key();
  if (!key) return ssl_error("generating a P-256 key");
  auto cert = make_cert(key.get(), common_name, ca_cert.get(), ca_key.get(), v, false);
  if (!cert) return cert.error();
  return KeyPair{cert_pem(cert->get()), key_pem(key.get())};
}

core::Result<std::string> smime_sign(const KeyPair& ca, const std::string& document) {
  X509Ptr ca_cert = read_cert(ca.cert);
  PkeyPtr ca_key = read_key(ca.key);
  if (!ca_cert || !ca_key) return ssl_error("reading the CA");
  // Detached (multipart/signed) with a text/plain part: the form of
  // `openssl smime -sign -text`, which both vendors' plugins read.
  const int flags = PKCS7_DETACHED | PKCS7_STREAM | PKCS7_TEXT;
  BioPtr in = mem_bio(document);
  Pkcs7Ptr p7(PKCS7_sign(ca_cert.get(), ca_key.get(), nullptr, in.get(), flags));
  if (!p7) return ssl_error("PKCS7_sign");
  BioPtr out(BIO_new(BIO_s_mem()));
  BioPtr again = mem_bio(document);
  if (SMIME_write_PKCS7(out.get(), p7.get(), again.get(), flags) != 1) return ssl_error("SMIME_write_PKCS7");
  return bio_string(out.get());
}

bool smime_verify(const std::string& ca_cert, const std::string& smime, std::string* content) {
  X509Ptr ca = read_cert(ca_cert);
  if (!ca) return false;
  StorePtr store(X509_STORE_new());
  X509_STORE_add_cert(store.get(), ca.get());
  BioPtr in = mem_bio(smime);
  BIO* detached = nullptr;
  Pkcs7Ptr p7(SMIME_read_PKCS7(in.get(), &detached));
  BioPtr cont(detached);
  if (!p7) {
    ERR_clear_error();
    return false;
  }
  BioPtr out(BIO_new(BIO_s_mem()));
  const bool ok = PKCS7_verify(p7.get(), nullptr, store.get(), cont.get(), out.get(), PKCS7_TEXT) == 1;
  ERR_clear_error();
  if (ok && content != nullptr) *content = bio_string(out.get());
  return ok;
}

}  // namespace pheromesh::auth
