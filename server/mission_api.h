#pragma once
// One mission's REST API and live events (/api/...; see server/README.md),
// for `seamap serve MAP` (prefix "") and for each mission of a catalogue
// (prefix "/missions/([a-z0-9_-]+)", the mission found from the request).
#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "server/detection_registry.h"
#include "server/event_hub.h"
#include "server/mission_state.h"
#include "server/server_options.h"

namespace httplib {
class Server;
struct Request;
}  // namespace httplib

namespace seamap::server {

struct MissionServices {
  MissionState* mission = nullptr;
  DetectionRegistry* detections = nullptr;
  EventHub* events = nullptr;  // must outlive the server: open streams keep reading it
  // Keeps a catalogue mission's records alive while a request or an event
  // stream uses them, though the catalogue closes it meanwhile (replaced, or
  // least recently used); empty for the root map, which outlives the server.
  std::shared_ptr<const void> keep;
};

// The mission a request is for; throws ApiError (404) when there is none.
using MissionResolver = std::function<MissionServices(const httplib::Request&)>;

// Adds the API routes to `s` under `prefix` (a regex holding `prefix_groups`
// capture groups, which come before the routes' own). Options used: token,
// photo_dir, max_streams; `streams` counts the open event streams.
void AddMissionApi(httplib::Server& s, const std::string& prefix, int prefix_groups, MissionResolver resolve,
                   const ServerOptions& options, std::atomic<int>* streams);

}  // namespace seamap::server
