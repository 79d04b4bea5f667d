-- Trial pictures: what the robot's camera saw around the tag, at most one per trial.
--
-- A picture retention removed keeps its row (bytes null, digest kept), so a robot that sends
-- it again from its outbox is answered as a retry, not stored anew.

create table trial_pictures (
    trial        text collate "C" not null primary key references trials (id),
    media_type   text collate "C" not null check (media_type in ('image/png', 'image/jpeg')),
    bytes        bytea,                               -- null once retention removed it
    sha256       text collate "C" not null,           -- of the bytes as sent; the ETag
    size         bigint not null,
    width        bigint not null,
    height       bigint not null,
    received_at  text collate "C" not null,
    removed_at   text collate "C"                     -- when retention removed the bytes
);
