-- A robot that cannot do a task declines it with a reason in words: the task goes back to the
-- queue for the others and is never offered to that robot again.
alter table tasks add column declines text collate "C" not null default '[]';  -- JSON array: {robot, reason, at}
