// A GoogleTest test written as one for upstream's RTC interface is (the headers, the fixture
// that reaches the class's private `updateCooperateCommandStatus` and `stored_commands_` as its
// friend, `rclcpp::Time`, a generated UUID), built by `tools/cpp-upstream` with the shim: what
// upstream's own test needs compiles, links and runs here. Every assertion holds on an interface
// with a binding.
#include "autoware/rtc_interface/rtc_interface.hpp"

#include <autoware/universe_utils/ros/uuid_helper.hpp>
#include <rclcpp/node.hpp>
#include <rclcpp/time.hpp>

#include "tier4_rtc_msgs/msg/detail/command__struct.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace autoware::rtc_interface
{
class RTCInterfaceTest : public ::testing::Test
{
public:
  void command(const std::vector<CooperateCommand> & commands)
  {
    rtc_->updateCooperateCommandStatus(commands);
  }
  std::vector<CooperateCommand> stored() const { return rtc_->stored_commands_; }

protected:
  void SetUp() override
  {
    rclcpp::init(0, nullptr);
    node_ = std::make_shared<rclcpp::Node>("fixture");
    rtc_ = std::make_shared<RTCInterface>(node_.get(), "lane_change_left", false);
  }
  void TearDown() override { rclcpp::shutdown(); }

  rclcpp::Node::SharedPtr node_;
  std::shared_ptr<RTCInterface> rtc_;
};

TEST_F(RTCInterfaceTest, the_friend_reaches_the_command_path_and_nothing_is_stored)
{
  const auto id = autoware::universe_utils::generateUUID();
  const rclcpp::Time stamp(1, 0);
  rtc_->updateCooperateStatus(id, false, tier4_rtc_msgs::msg::State::RUNNING, 10.0, 100.0, stamp);
  EXPECT_TRUE(rtc_->isRegistered(id));
  EXPECT_FALSE(rtc_->isActivated(id));

  CooperateCommand activate;
  activate.uuid = id;
  activate.command.type = tier4_rtc_msgs::msg::Command::ACTIVATE;
  command({activate});
  EXPECT_TRUE(rtc_->isActivated(id));
  EXPECT_TRUE(rtc_->isForceActivated(id));
  EXPECT_TRUE(stored().empty());

  CooperateCommand unknown = activate;
  unknown.uuid = autoware::universe_utils::generateUUID();
  command({unknown});
  EXPECT_FALSE(rtc_->isRegistered(unknown.uuid));
  EXPECT_TRUE(stored().empty());
}
}  // namespace autoware::rtc_interface
