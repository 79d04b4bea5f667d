-- The Home Assistant bridge's lease: of several replicas on one registry, only the holder
-- runs the bridge, so each press on a button becomes at most one task.

create table bridge_lease (
    bridge  text collate "C" not null primary key,   -- which bridge ('home_assistant')
    holder  text collate "C" not null,               -- the replica holding it (random per process)
    until   text collate "C" not null                -- when it runs out unless renewed
);
