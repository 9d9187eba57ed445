#pragma once
// The status socket's answers printed for people on stdout, as poetctl shows them: tables with columns sized
// to their widest cell and numbers right-aligned, one line per event. The server's strings are printed with their
// control characters written out (common/text/utf8.h's printable_text): they cannot drive the terminal.

#include <google/protobuf/struct.pb.h>

#include "common/text/event_text.h"
#include "status.pb.h"

namespace poet {

void print_status(const status::Status& status);
void print_pairs(const status::PairList& list);
void print_pair(const status::PairDetail& detail);
void print_archive(const status::Archive& archive);
void print_workers(const status::WorkerList& list);
// Each event as describe_event writes it, then where the next page starts.
void print_events(const status::EventList& list);

// An event of /events: its fields sorted by name (a protobuf map has no order), numbers written out in full
// when whole.
EventView event_view(const google::protobuf::Struct& event);

}  // namespace poet
