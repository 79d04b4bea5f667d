-- Tasks: a caretaker asks for an action on a tag; one robot at a time holds it under a lease.

create table tasks (
    seq           integer primary key autoincrement,  -- the order tasks were asked for
    id            text not null unique,               -- UUID chosen by the registry
    epc           text not null,                      -- follows the tag when it is retagged
    action        text not null,
    robot         text,                               -- only this robot may do it
    class         text,                               -- only robots of this class may do it
    note          text,
    state         text not null check (state in ('queued', 'claimed', 'done', 'failed', 'cancelled')),
    created_by    text not null,
    created_at    text not null,
    claimed_by    text,                               -- the holder; after the end, who ended it
    lease_until   text,                               -- when the holder's lease runs out
    attempts      integer not null default 0,         -- how many times it was claimed
    holders       text not null default '[]',         -- JSON array: every robot that held it
    trial         text,                               -- the trial it ended in
    reason        text,                               -- why it failed or was cancelled
    updated_at    text not null,
    check (state != 'claimed' or (claimed_by is not null and lease_until is not null)),
    check (state != 'queued' or (claimed_by is null and lease_until is null))
) strict;

-- Claims look for the oldest queued tasks; the sweep for claimed ones whose lease ran out.
create index tasks_by_state on tasks (state, seq);
create index tasks_by_lease on tasks (lease_until) where state = 'claimed';
create index tasks_by_epc on tasks (epc, seq);
