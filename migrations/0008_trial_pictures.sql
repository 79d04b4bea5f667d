-- Trial pictures: what the robot's camera saw around the tag, at most one per trial.
--
-- A picture retention removed keeps its row (bytes null, digest kept), so a robot that sends
-- it again from its outbox is answered as a retry, not stored anew.

create table trial_pictures (
    trial        text not null primary key references trials (id),
    media_type   text not null check (media_type in ('image/png', 'image/jpeg')),
    bytes        blob,                                -- null once retention removed it
    sha256       text not null,                       -- of the bytes as sent; the ETag
    size         integer not null,
    width        integer not null,
    height       integer not null,
    received_at  text not null,
    removed_at   text                                 -- when retention removed the bytes
) strict;
