#include "coordinator/dispatch/outgoing.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <cstring>

namespace poet {
namespace {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedOutputStream;

uint32_t delimited_tag(int field) { return WireFormatLite::MakeTag(field, WireFormatLite::WIRETYPE_LENGTH_DELIMITED); }

size_t thetas_size(const Outgoing& message) {
  size_t size = 0;
  for (const auto& field : message.job_thetas) size += field->size();
  return size;
}

}  // namespace

size_t Outgoing::frame_size() const {
  if (job_thetas.empty()) return message.ByteSizeLong();
  const size_t job = message.job().ByteSizeLong() + thetas_size(*this);
  const uint32_t tag = delimited_tag(wire::CoordinatorMessage::kJobFieldNumber);
  return CodedOutputStream::VarintSize32(tag) + CodedOutputStream::VarintSize64(job) + job;
}

void Outgoing::write_frame(char* out) const {
  auto* at = reinterpret_cast<uint8_t*>(out);
  if (job_thetas.empty()) {
    message.SerializeWithCachedSizesToArray(at);
    return;
  }
  const size_t job = static_cast<size_t>(message.job().GetCachedSize()) + thetas_size(*this);
  at = CodedOutputStream::WriteVarint32ToArray(delimited_tag(wire::CoordinatorMessage::kJobFieldNumber), at);
  at = CodedOutputStream::WriteVarint64ToArray(job, at);
  at = message.job().SerializeWithCachedSizesToArray(at);
  for (const auto& field : job_thetas) {
    std::memcpy(at, field->data(), field->size());
    at += field->size();
  }
}

std::string Outgoing::frame() const {
  std::string bytes(frame_size(), '\0');
  write_frame(bytes.data());
  return bytes;
}

std::string encode_theta_field(uint64_t hash, std::span<const double> values) {
  wire::Job carrier;  // a Job holding only this θ is exactly its Job.thetas field
  wire::Theta* theta = carrier.add_thetas();
  theta->set_hash(hash);
  theta->mutable_values()->Add(values.begin(), values.end());
  return carrier.SerializeAsString();
}

Outgoing heartbeat_to(const WorkerId& to) {
  Outgoing out(to);
  out.message.mutable_heartbeat();
  return out;
}

Outgoing refusal_to(const WorkerId& to, const std::string& reason) {
  Outgoing out(to);
  out.message.mutable_refused()->set_reason(reason);
  return out;
}

}  // namespace poet
