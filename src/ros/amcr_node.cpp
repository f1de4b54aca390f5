// amcr_node: amcr/RecognizerNodelet in a process of its own (as image_proc's
// image_proc node loads its nodelets). Same topics, services and parameters.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "amcr");
  nodelet::Loader manager(false);
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string my_argv;
  if (!manager.load(ros::this_node::getName(), "amcr/RecognizerNodelet", remappings, my_argv))
  {
    ROS_FATAL("cannot load the nodelet amcr/RecognizerNodelet (is the package built and sourced?)");
    return 1;
  }
  ros::spin();
  return 0;
}
