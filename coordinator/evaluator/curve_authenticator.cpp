#include "coordinator/evaluator/curve_authenticator.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <sstream>
#include <vector>

#include "common/plumbing/curve_keys.h"
#include "common/plumbing/text_file.h"
#include "run_directory/files/run_directory.h"

namespace poet {
namespace {

constexpr char kZapEndpoint[] = "inproc://zeromq.zap.01";
constexpr size_t kRequestFrames = 7;  // version, request id, domain, address, identity, mechanism, key

std::string z85(const zmq::message_t& key) {
  if (key.size() != 32) return "(not a 32-byte key)";
  std::array<char, 41> text{};
  zmq_z85_encode(text.data(), static_cast<const uint8_t*>(key.data()), key.size());
  return text.data();
}

}  // namespace

CurveAuthenticator::CurveAuthenticator(zmq::context_t& context, std::filesystem::path key_dir,
                                       std::function<void()> skipped_key_file, std::filesystem::path refused_keys_file)
    : socket_(context, zmq::socket_type::rep),
      key_dir_(std::move(key_dir)),
      skipped_key_file_(std::move(skipped_key_file)),
      refused_keys_file_(std::move(refused_keys_file)) {
  // a run that refused no worker has no such file: absence is the read's own answer, not a problem
  const Expected<std::string> text = refused_keys_file_.empty()
                                         ? Expected<std::string>(Unexpected{kDoesNotExist})
                                         : read_text_file(refused_keys_file_, kMaxRefusedKeysBytes);
  if (!text) {
    if (text.error() != kDoesNotExist)
      spdlog::warn("CURVE: {}: {}; no worker key is refused from it", refused_keys_file_.string(), text.error());
  } else {
    std::istringstream lines(*text);
    for (std::string line; std::getline(lines, line);)
      if (is_z85_key(line)) refused_keys_.insert(line);
    if (!refused_keys_.empty())
      spdlog::info("CURVE: {} worker key(s) refused for wrong results earlier in this run ({})", refused_keys_.size(),
                   refused_keys_file_.string());
  }
  socket_.set(zmq::sockopt::linger, 0);
  socket_.bind(kZapEndpoint);
  // the files already bad at start are skipped, logged and counted then, as those that turn bad later are
  if (Expected<AuthorizedKeys> authorized = scan_authorized_keys(key_dir_)) note_bad_files(authorized->bad_files);
}

bool CurveAuthenticator::answer_one(std::string& key, std::string& reason) {
  std::vector<zmq::message_t> request;
  zmq::message_t frame;
  if (!socket_.recv(frame, zmq::recv_flags::dontwait)) return false;
  request.push_back(std::move(frame));
  while (request.back().more()) {
    zmq::message_t part;
    if (!socket_.recv(part, zmq::recv_flags::dontwait)) break;
    request.push_back(std::move(part));
  }
  // libzmq writes these requests itself; still, nothing is assumed about their shape
  const bool well_formed = request.size() == kRequestFrames && request[0].to_string_view() == "1.0" &&
                           request[5].to_string_view() == "CURVE";
  key = well_formed ? z85(request[6]) : "";
  if (!well_formed) {
    reason = "not a CURVE request";
  } else if (Expected<AuthorizedKeys> authorized = scan_authorized_keys(key_dir_); !authorized) {
    reason = authorized.error();
  } else {
    note_bad_files(authorized->bad_files);
    if (refused_keys_.contains(key))
      reason = "its public key was refused in this run: a worker holding it returned wrong results";
    else if (!std::binary_search(authorized->keys.begin(), authorized->keys.end(), key))
      reason = "its public key is not in " + (key_dir_ / "authorized").string();
  }
  const std::string request_id = request.size() > 1 ? request[1].to_string() : "";
  const std::string status = reason.empty() ? "200" : "400";
  socket_.send(zmq::str_buffer("1.0"), zmq::send_flags::sndmore);
  socket_.send(zmq::buffer(request_id), zmq::send_flags::sndmore);
  socket_.send(zmq::buffer(status), zmq::send_flags::sndmore);
  socket_.send(zmq::buffer(reason.empty() ? std::string("OK") : reason), zmq::send_flags::sndmore);
  socket_.send(zmq::buffer(key), zmq::send_flags::sndmore);  // user id: the key
  socket_.send(zmq::str_buffer(""), zmq::send_flags::none);  // no metadata
  return true;
}

void CurveAuthenticator::refuse(const std::string& key) {
  if (!refused_keys_.insert(key).second || refused_keys_file_.empty()) return;
  std::string text;
  for (const std::string& k : refused_keys_) text += k + "\n";
  if (const auto error = write_file_atomically(refused_keys_file_, text))
    spdlog::error("CURVE: {}: {}; the key stays refused until the coordinator stops", refused_keys_file_.string(),
                  *error);
}

void CurveAuthenticator::note_bad_files(const std::map<std::string, std::string>& bad_files) {
  std::erase_if(bad_files_, [&](const std::string& path) { return !bad_files.contains(path); });
  for (const auto& [path, problem] : bad_files) {
    if (!bad_files_.insert(path).second) continue;
    spdlog::warn("CURVE: skipped {}; the other authorised keys still work", problem);
    if (skipped_key_file_) skipped_key_file_();
  }
}

}  // namespace poet
