-- Why each trial was made: real use, an experiment or a test. Success rates, reliability and
-- learning count real use unless asked otherwise, so an experiment's deliberate failures do
-- not count against a tag. Every trial recorded before is real use.

alter table trials add column purpose text collate "C" not null default 'use'
    check (purpose in ('use', 'experiment', 'test'));

-- The look-ups of learning and reliability now also name the purpose; these replace the
-- indexes of 0001 so they still match those expressions exactly.
drop index trials_by_action_class;
drop index trials_by_behavior_class;
create index trials_by_action_class on trials (epc, action, coalesce(robot_class, ''), purpose, seq);
create index trials_by_behavior_class on trials (epc, behavior, coalesce(robot_class, ''), purpose, seq);
