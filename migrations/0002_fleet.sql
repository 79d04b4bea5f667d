-- The fleet: robots, their trials, what was learned from them, unknown tags robots read,
-- retired EPCs, and the change feed.

create table robots (
    id          text primary key not null,
    class       text,
    document    text not null,              -- the robot as PUT (JSON), read-only fields stripped
    updated_at  text not null,
    updated_by  text not null
) strict;

-- When each robot last called the API; kept in memory and flushed now and then.
create table robot_presence (
    robot       text primary key not null,
    last_seen   text not null
) strict;

create table trials (
    seq          integer primary key autoincrement,  -- the registry's order of receipt
    id           text not null unique,               -- chosen by the robot: a retry is a no-op
    epc          text not null,
    robot        text not null,
    robot_class  text,                               -- the robot's class when it was recorded
    action       text not null,
    behavior     text not null,
    outcome      text not null check (outcome in ('success', 'failure', 'aborted', 'error')),
    confirmed    integer check (confirmed in (0, 1)), -- the person's verdict; null until given
    started_at   text not null,
    finished_at  text not null,
    received_at  text not null,
    body         text not null                        -- the trial as PUT (JSON)
) strict;

create index trials_by_epc on trials (epc, seq);
create index trials_by_robot on trials (robot, seq);
create index trials_by_group on trials (epc, action, robot_class, seq);

-- Values learned from a robot class's trials, merged into effective entries at `learned`.
create table learned_values (
    epc          text not null,
    robot_class  text not null,               -- '' for robots without a class
    pointer      text not null,               -- JSON pointer into the entry, e.g. /behaviors/pull_open/pull_distance
    value        real not null,
    trials       integer not null,            -- how many trials the value rests on
    updated_at   text not null,
    primary key (epc, robot_class, pointer)
) strict;

-- The last reliability verdict per action and robot class, to notice when it changes.
create table reliability (
    epc          text not null,
    action       text not null,
    robot_class  text not null,
    reliable     integer not null,
    primary key (epc, action, robot_class)
) strict;

-- EPCs robots read that nobody registered.
create table inbox (
    epc          text primary key not null,
    robots       text not null,               -- JSON array of robot ids
    first_seen   text not null,
    last_seen    text not null,
    count        integer not null
) strict;

-- Worn tags replaced by a new one: the old EPC points at its successor.
create table retired_epcs (
    epc          text primary key not null,
    successor    text not null,
    retired_at   text not null,
    retired_by   text not null
) strict;

-- The change feed; ids are the SSE event ids, so a client resumes across restarts.
create table events (
    id           integer primary key autoincrement,
    kind         text not null,
    data         text not null,               -- JSON naming the thing that changed
    created_at   text not null
) strict;
