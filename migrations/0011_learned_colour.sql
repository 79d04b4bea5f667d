-- Colour models learned from confirmed reads (trials carrying `tag_color`): one per tag and
-- robot class, and one per robot class for the household (epc '').

create table learned_colours (
    epc          text not null,               -- '' for the household's model
    robot_class  text not null,               -- '' for robots without a class
    model        text not null,               -- {"hue_deg", "saturation", "value", "trials"} (JSON)
    trials       integer not null,            -- how many reads the model rests on
    updated_at   text not null,
    primary key (epc, robot_class)
) strict;
