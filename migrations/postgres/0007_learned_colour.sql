-- Colour models learned from confirmed reads (trials carrying `tag_color`): one per tag and
-- robot class, and one per robot class for the household (epc '').

create table learned_colours (
    epc          text collate "C" not null,     -- '' for the household's model
    robot_class  text collate "C" not null,     -- '' for robots without a class
    model        text collate "C" not null,     -- {"hue_deg", "saturation", "value", "trials"} (JSON)
    trials       bigint not null,               -- how many reads the model rests on
    updated_at   text collate "C" not null,
    primary key (epc, robot_class)
);
