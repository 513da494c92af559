#include "server/detection_registry.h"

#include "server/api_error.h"
#include "server/http/http_util.h"

namespace seamap::server {
namespace {

// Runs a book call, answering its refusal as the API's error.
template <typename F>
auto Answer(F f) -> decltype(f()) {
  try {
    return f();
  } catch (const DetectionError& e) {
    throw ApiError(HttpStatus(e.kind()), e.what());
  }
}

}  // namespace

int HttpStatus(DetectionError::Kind kind) {
  switch (kind) {
    case DetectionError::Kind::kNotFound:
      return 404;
    case DetectionError::Kind::kInvalid:
      return 400;
    case DetectionError::Kind::kRefused:
      return 403;
  }
  return 500;
}

DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since, const std::optional<std::string>& status,
                                     const std::optional<std::string>& source) {
  try {
    return seamap::ParseDetectionFilter(bbox, classes, min_score, since, status, source);
  } catch (const DetectionError& e) {
    throw ApiError(HttpStatus(e.kind()), "parameter '" + e.field() + "': " + e.detail());
  }
}

DetectionRegistry::DetectionRegistry(TileStore* store, EventHub* events)
    : book_(store, [events](const char* action, const Detection& d) {
        if (!events) return;
        nlohmann::json data = {{"action", action}, {"id", d.id}};
        data["feature"] = std::string(action) == "deleted" ? nlohmann::json(nullptr) : DetectionFeature(d);
        events->Publish("detection", Dump(data));  // a class or note need not be UTF-8
      }) {}

nlohmann::json DetectionRegistry::Query(const DetectionFilter& filter) const {
  int64_t last_seq = 0;
  nlohmann::json features = nlohmann::json::array();
  for (const Detection& d : book_.Query(filter, &last_seq)) features.push_back(DetectionFeature(d));
  return {{"type", "FeatureCollection"}, {"features", std::move(features)}, {"last_seq", last_seq}};
}

nlohmann::json DetectionRegistry::QueryPage(const DetectionFilter& filter, std::optional<int64_t> after_id,
                                            size_t limit, bool* more) const {
  const DetectionPage page = book_.QueryPage(filter, after_id, limit);
  nlohmann::json features = nlohmann::json::array();
  for (const Detection& d : page.detections) features.push_back(DetectionFeature(d));
  *more = page.more;
  return {{"type", "FeatureCollection"}, {"features", std::move(features)}, {"last_seq", page.last_seq}};
}

std::optional<nlohmann::json> DetectionRegistry::Get(int64_t id) const {
  const std::optional<Detection> d = book_.Get(id);
  if (!d) return std::nullopt;
  return DetectionFeature(*d);
}

nlohmann::json DetectionRegistry::Create(const nlohmann::json& feature) {
  return DetectionFeature(Answer([&] { return book_.Create(feature); }));
}

nlohmann::json DetectionRegistry::Update(int64_t id, const nlohmann::json& patch) {
  return DetectionFeature(Answer([&] { return book_.Update(id, patch); }));
}

void DetectionRegistry::Delete(int64_t id) {
  Answer([&] { book_.Delete(id); });
}

PublishResult DetectionRegistry::Publish(std::vector<Detection> batch, const PublishOptions& options) {
  return Answer([&] { return book_.Publish(std::move(batch), options); });
}

}  // namespace seamap::server
