-- The Home Assistant bridge's lease: of several processes on one registry, only the holder
-- runs the bridge, so each press on a button becomes at most one task.

create table bridge_lease (
    bridge  text not null primary key,   -- which bridge ('home_assistant')
    holder  text not null,               -- the process holding it (a random id per process)
    until   text not null                -- when it runs out unless renewed (stored time format)
) strict;
