-- A task no robot took in time expires: it is cancelled, and its reason says so. Null: never
-- (tasks asked for before tasks could expire).
alter table tasks add column expires_at text collate "C";

-- Expired tasks are looked for among the queued ones.
create index tasks_by_expiry on tasks (expires_at) where state = 'queued';
-- Each claim counts the tasks its robot holds (one robot holds at most a few at once).
create index tasks_by_holder on tasks (claimed_by) where state = 'claimed';
-- A trial finishes one task: a finish looks whether its trial finished another.
create index tasks_by_trial on tasks (trial) where trial is not null;
