#pragma once
// The coordinator's ZAP handler (ZeroMQ RFC 27) for CURVE: every worker's handshake asks it whether the client's
// public key is one of DIR/authorized/*.key. The folder is read at each handshake, so a key copied in takes effect
// for the next connection, without a restart. A worker whose key is refused never gets a connection: it can
// neither be sent work nor submit any. A file there that holds no key (half-copied, garbage), at start or later, is
// skipped: logged once and counted, while the other keys go on working. A key refused for wrong results (refuse)
// stays refused for the run, whatever socket it comes back on, and across a resume: the keys are kept in a file of
// the run directory, read at start.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <zmq.hpp>

namespace poet {

class CurveAuthenticator {
 public:
  // Binds the ZAP endpoint in `context`; it must exist before a CURVE socket of that context binds. Throws
  // zmq::error_t when it cannot. skipped_key_file, when given, is called once for each file of authorized/ found
  // to hold no key (again if it is fixed and then spoiled again): here for those bad at start, then on the thread
  // that calls answer_all.
  CurveAuthenticator(zmq::context_t& context, std::filesystem::path key_dir,
                     std::function<void()> skipped_key_file = {}, std::filesystem::path refused_keys_file = {});

  // Refuses key (Z85) from now on, in this run and after a resume; written to refused_keys_file when given.
  void refuse(const std::string& key);

  zmq::socket_t& socket() { return socket_; }

  // Answers every request waiting. `denied` is called for each refused handshake with the client's public key
  // (Z85) and why.
  template <typename OnDenied>
  void answer_all(OnDenied&& denied) {
    for (int n = 0; n < kMaxPerTurn; ++n) {
      std::string key, reason;
      if (!answer_one(key, reason)) return;
      if (!reason.empty()) denied(key, reason);
    }
  }

 private:
  static constexpr int kMaxPerTurn = 256;
  // False when no request was waiting; otherwise answers it, and sets reason when it was refused.
  bool answer_one(std::string& key, std::string& reason);
  // logs and counts the files newly found bad; forgets those fixed or gone
  void note_bad_files(const std::map<std::string, std::string>& bad_files);

  zmq::socket_t socket_;
  std::filesystem::path key_dir_;
  std::function<void()> skipped_key_file_;
  std::set<std::string> bad_files_;  // the paths logged already
  std::filesystem::path refused_keys_file_;
  std::set<std::string> refused_keys_;  // Z85
};

}  // namespace poet
