#include "web_view.h"

#include <geometry_msgs/Twist.h>
#include <ros/callback_queue.h>

#include <boost/make_shared.hpp>
#include <sstream>

#include "bullet_sim/assets/package_resolver.h"
#include "ros_parameters.h"

namespace bullet_sim {

namespace {

/// A function that the callback queue runs, between steps.
class QueuedCall final : public ros::CallbackInterface {
 public:
  explicit QueuedCall(std::function<void()> call) : call_(std::move(call)) {}
  CallResult call() override {
    call_();
    return Success;
  }

 private:
  std::function<void()> call_;
};

std::vector<std::string> originsParam(const ros::NodeHandle& private_node) {
  XmlRpc::XmlRpcValue value;
  if (!private_node.getParam("web_allowed_origins", value)) return {};
  std::vector<std::string> origins;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString) {
    std::string text = value;
    for (char& c : text) c = c == ',' ? ' ' : c;
    std::istringstream words(text);
    for (std::string origin; words >> origin;) origins.push_back(origin);
    return origins;
  }
  const std::string expected =
      "~web_allowed_origins must be a list of origins (\"http://host:port\") or one string of them";
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray) throw std::runtime_error(expected);
  for (int i = 0; i < value.size(); ++i) {
    if (value[i].getType() != XmlRpc::XmlRpcValue::TypeString) throw std::runtime_error(expected);
    origins.push_back(static_cast<std::string>(value[i]));
  }
  return origins;
}

/// The id under which a view's commands wait in the callback queue.
uint64_t queueId(const NodeWebView* view) { return reinterpret_cast<uint64_t>(view); }

}  // namespace

std::unique_ptr<NodeWebView> NodeWebView::fromParameters(const ros::NodeHandle& private_node,
                                                         Actions actions) {
  const int port = wholeParam(private_node, "web_port", 0);
  if (port == 0) return nullptr;
  if (port < 0 || port > 65535) {
    throw std::runtime_error("~web_port must be a TCP port, 1 to 65535 (0: no viewer), not " +
                             std::to_string(port));
  }
  WebViewerOptions options;
  options.port = static_cast<uint16_t>(port);
  options.address = textParam(private_node, "web_address", options.address);
  options.allowed_origins = originsParam(private_node);
  options.control_beyond_localhost = flagParam(private_node, "web_control", false);
  const auto package = PackageResolver::fromEnvironment().packageDirectory("bullet_sim");
  options.page_dir = package.value_or(".") + "/web";

  std::unique_ptr<NodeWebView> view(new NodeWebView(std::move(actions)));
  NodeWebView* queued = view.get();
  try {
    view->viewer_ = std::make_unique<WebViewer>(options, [queued](const ViewerCommand& command) {
      ros::getGlobalCallbackQueue()->addCallback(
          boost::make_shared<QueuedCall>([queued, command] { queued->apply(command); }), queueId(queued));
    });
  } catch (const std::runtime_error& e) {
    ROS_ERROR("~web_port %d: no web viewer: %s. The simulation runs on without it.", port, e.what());
    return nullptr;
  }
  ROS_INFO("web viewer: http://%s:%d/ (pages from other machines %s)",
           options.address == "0.0.0.0" ? "localhost" : options.address.c_str(), port,
           options.control_beyond_localhost ? "may pause, reset and drive: ~web_control" : "may only watch");
  return view;
}

NodeWebView::~NodeWebView() {
  viewer_.reset();  // its thread queues nothing more
  ros::getGlobalCallbackQueue()->removeByID(queueId(this));
}

void NodeWebView::apply(const ViewerCommand& command) {
  switch (command.kind) {
    case ViewerCommand::Kind::kPause: actions_.pause(); break;
    case ViewerCommand::Kind::kResume: actions_.resume(); break;
    case ViewerCommand::Kind::kReset: actions_.reset(); break;
    case ViewerCommand::Kind::kTeleop: teleop(command); break;
  }
}

void NodeWebView::teleop(const ViewerCommand& command) {
  const std::string topic = actions_.velocity_topic(command.robot);
  if (topic.empty()) {
    ROS_WARN_THROTTLE(5,
                      "web viewer: robot [%s] is gone or takes no velocity commands: its teleop is ignored",
                      command.robot.c_str());
    return;
  }
  auto publisher = velocity_publishers_.find(topic);
  if (publisher == velocity_publishers_.end()) {
    publisher =
        velocity_publishers_.emplace(topic, ros::NodeHandle().advertise<geometry_msgs::Twist>(topic, 10))
            .first;
  }
  geometry_msgs::Twist twist;
  twist.linear.x = command.linear;
  twist.angular.z = command.angular;
  publisher->second.publish(twist);
}

}  // namespace bullet_sim
