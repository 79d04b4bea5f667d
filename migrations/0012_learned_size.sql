-- Tag sizes learned from confirmed reads (trials carrying `tag_size`): one per tag, whichever
-- robot measured it, since a tag's size is the tag's own, not the camera's.

create table learned_sizes (
    epc          text primary key not null,
    width        real not null,               -- metres
    height       real not null,               -- metres
    trials       integer not null,            -- how many measurements the size rests on
    updated_at   text not null
) strict;
