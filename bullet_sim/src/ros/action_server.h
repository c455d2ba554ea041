// A plugin's action served through actionlib: each goal and cancel request goes to the plugin's handlers as
// it arrives (between steps, on the node's thread), and what the plugin reports goes out as feedback and
// results. One ActionBridge per action type, given its messages (e.g. FollowJointTrajectoryMessages): the
// action's ROS type and the conversions of its goal, feedback and result.
#pragma once

#include <actionlib/server/action_server.h>
#include <ros/ros.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "bullet_sim/plugins/ports.h"

namespace bullet_sim {

class ActionConnection {
 public:
  virtual ~ActionConnection() = default;
  /// Sends what the plugin reported since the last call.
  virtual void sendReports() = 0;
  /// The action's resolved name, for the log.
  virtual std::string name() const = 0;
};

template <class Messages>
class ActionBridge : public ActionConnection {
  using Action = typename Messages::Action;
  using Server = actionlib::ActionServer<typename Messages::RosAction>;
  using GoalHandle = typename Server::GoalHandle;
  using Report = typename GoalReports<Action>::Report;

 public:
  ActionBridge(const ros::NodeHandle& handle, const std::string& name, ActionHandlers<Action> handlers,
               std::function<double()> sim_time, std::string robot)
      : handlers_(std::move(handlers)),
        sim_time_(std::move(sim_time)),
        robot_(std::move(robot)),
        name_(handle.resolveName(name)),
        server_(
            handle, name, [this](GoalHandle goal) { onGoal(goal); },
            [this](GoalHandle goal) { onCancel(goal); }, false) {
    server_.start();
  }
  ~ActionBridge() override { sendReports(); }

  void sendReports() override { send(handlers_.reports->take()); }
  std::string name() const override { return name_; }

 private:
  void onGoal(GoalHandle goal) {
    const GoalId id = next_id_++;
    const GoalDecision<Action> decision = handlers_.goal(id, Messages::goal(*goal.getGoal()), sim_time_());
    if (!decision.accepted) {
      ROS_WARN("[%s] %s: goal rejected: %s", robot_.c_str(), name_.c_str(),
               decision.result.error_string.c_str());
      goal.setRejected(Messages::result(decision.result), decision.result.error_string);
      return;
    }
    // The goals it ended in taking this one (the one it preempts) end first, as actionlib servers do it.
    std::vector<Report> reports = handlers_.reports->take();
    std::vector<Report> own;
    for (auto it = reports.begin(); it != reports.end();) {
      if (it->goal == id) {
        own.push_back(*it);
        it = reports.erase(it);
      } else {
        ++it;
      }
    }
    send(reports);
    goal.setAccepted();
    goals_.emplace(id, goal);
    send(own);
  }

  void onCancel(GoalHandle goal) {
    for (const auto& [id, handle] : goals_) {
      if (handle == goal) {
        handlers_.cancel(id, sim_time_());
        sendReports();
        return;
      }
    }
  }

  void send(const std::vector<Report>& reports) {
    for (const auto& report : reports) {
      const auto found = goals_.find(report.goal);
      if (found == goals_.end()) continue;
      GoalHandle& goal = found->second;
      if (!report.end) {
        goal.publishFeedback(Messages::feedback(report.feedback));
        continue;
      }
      const auto result = Messages::result(report.result);
      switch (*report.end) {
        case GoalEnd::kSucceeded:
          goal.setSucceeded(result, report.result.error_string);
          break;
        case GoalEnd::kAborted:
          ROS_WARN("[%s] %s: goal aborted: %s", robot_.c_str(), name_.c_str(),
                   report.result.error_string.c_str());
          goal.setAborted(result, report.result.error_string);
          break;
        case GoalEnd::kCanceled:
          goal.setCanceled(result, report.result.error_string);
          break;
      }
      goals_.erase(found);
    }
  }

  ActionHandlers<Action> handlers_;
  std::function<double()> sim_time_;
  std::string robot_;
  std::string name_;
  std::map<GoalId, GoalHandle> goals_;  ///< accepted and not yet ended
  GoalId next_id_ = 1;
  Server server_;  ///< last: its callbacks use the members above
};

}  // namespace bullet_sim
