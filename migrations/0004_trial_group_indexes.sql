-- Learning and reliability look up a tag's recent trials per action or behaviour and robot
-- class, where a robot without a class counts as class ''. These indexes match those
-- expressions exactly, so the look-ups stay fast however many trials accumulate.

drop index trials_by_group;
create index trials_by_action_class on trials (epc, action, coalesce(robot_class, ''), seq);
create index trials_by_behavior_class on trials (epc, behavior, coalesce(robot_class, ''), seq);
