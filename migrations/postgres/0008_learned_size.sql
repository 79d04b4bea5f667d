-- Tag sizes learned from confirmed reads (trials carrying `tag_size`): one per tag, whichever
-- robot measured it, since a tag's size is the tag's own, not the camera's.

create table learned_sizes (
    epc          text collate "C" primary key not null,
    width        double precision not null,     -- metres
    height       double precision not null,     -- metres
    trials       bigint not null,               -- how many measurements the size rests on
    updated_at   text collate "C" not null
);
